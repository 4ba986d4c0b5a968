//! L-system derivation and interpretation: lengths from an independent recurrence on symbol
//! counts, CPU results independent of the thread count, the sequential and parallel turtles in
//! exact agreement, a small system's segments worked out by hand, and parametric rules.

use std::collections::HashMap;

use glam::Vec3;
use grove::lsystem::grammar::Source;
use grove::lsystem::{Grammar, Limits, derive, derive_threads, presets, turtle};

/// The deterministic presets' axioms and rules, written out again here (not read from the
/// program) for the count recurrence.
const DETERMINISTIC: &[(&str, &str, &[(char, &str)])] = &[
    ("bush1", "Y", &[('X', "X[-FFF][+FFF]FX"), ('Y', "YFX[+Y][-Y]")]),
    ("bush2", "F", &[('F', "FF+[+F-F-F]-[-F+F+F]")]),
    ("bush3", "F", &[('F', "F[+FF][-FF]F[-F][+F]F")]),
    ("abop-a", "F", &[('F', "F[+F]F[-F]F")]),
    ("abop-b", "F", &[('F', "F[+F]F[-F][F]")]),
    ("abop-c", "F", &[('F', "FF-[-F+F+F]+[+F-F-F]")]),
    ("abop-d", "X", &[('X', "F[+X]F[-X]+X"), ('F', "FF")]),
    ("abop-e", "X", &[('X', "F[+X][-X]FX"), ('F', "FF")]),
    ("abop-f", "X", &[('X', "F-[[X]+X]+F[+FX]-X"), ('F', "FF")]),
];

/// Symbol counts after `n` steps: counts' = Σ_s counts[s] · occurrences in s's successor.
fn counts_by_recurrence(axiom: &str, rules: &[(char, &str)], n: u32) -> HashMap<char, u64> {
    let mut c: HashMap<char, u64> = HashMap::new();
    for ch in axiom.chars() {
        *c.entry(ch).or_default() += 1;
    }
    for _ in 0..n {
        let mut next: HashMap<char, u64> = HashMap::new();
        for (&s, &k) in &c {
            match rules.iter().find(|r| r.0 == s) {
                Some((_, succ)) => {
                    for t in succ.chars() {
                        *next.entry(t).or_default() += k;
                    }
                }
                None => *next.entry(s).or_default() += k,
            }
        }
        c = next;
    }
    c
}

#[test]
fn derived_lengths_and_counts_follow_the_count_recurrence() {
    let limits = Limits::default();
    for &(name, axiom, rules) in DETERMINISTIC {
        let g = presets::preset(name).unwrap();
        for n in 0..=5 {
            let want = counts_by_recurrence(axiom, rules, n);
            let s = derive(&g, n, 0, &limits).unwrap();
            assert_eq!(s.len() as u64, want.values().sum::<u64>(), "{name} n = {n}: length");
            let got = s.counts();
            for (&ch, &k) in &want {
                assert_eq!(got[ch as usize], k, "{name} n = {n}: count of {ch}");
            }
        }
    }
}

#[test]
fn bush2_lengths_match_the_closed_form() {
    // Each F becomes 8 F and 12 other symbols, so L(n) = 1 + 19 (8^n - 1) / 7; n = 7 gives the
    // issue's 5,692,268.
    let g = presets::preset("bush2").unwrap();
    let s = derive(&g, 7, 0, &Limits::default()).unwrap();
    assert_eq!(s.len() as u64, 1 + 19 * (8u64.pow(7) - 1) / 7);
    assert_eq!(s.len(), 5_692_268);
}

#[test]
fn one_and_two_threads_give_the_same_string_on_every_preset() {
    let limits = Limits::default();
    for name in presets::names() {
        let g = presets::preset(name).unwrap();
        // Enough steps to span several chunks where the grammar grows fast enough.
        let mut n = g.n;
        while n > 1 && derive(&g, n, 7, &limits).unwrap().len() > 2_000_000 {
            n -= 1;
        }
        let a = derive_threads(&g, n, 7, &limits, 1).unwrap();
        let b = derive_threads(&g, n, 7, &limits, 2).unwrap();
        assert_eq!(a.hash(), b.hash(), "{name} n = {n}");
        assert_eq!(a, b, "{name} n = {n}");
    }
}

#[test]
fn stochastic_rules_depend_on_the_seed_and_follow_their_weights() {
    let g = Grammar::compile(&Source {
        axiom: "A".repeat(200_000),
        rules: vec!["A -(1)-> B".into(), "A -(3)-> C".into()],
        ..Source::default()
    })
    .unwrap();
    let s = derive(&g, 1, 1, &Limits::default()).unwrap();
    let c = s.counts();
    let share = c[b'C' as usize] as f64 / 200_000.0;
    assert!((share - 0.75).abs() < 0.01, "share of C {share}");
    let t = derive(&g, 1, 2, &Limits::default()).unwrap();
    assert_ne!(s.hash(), t.hash());
    assert_eq!(s, derive(&g, 1, 1, &Limits::default()).unwrap());
}

#[test]
fn letters_without_rules_stay() {
    let g = Grammar::compile(&Source { axiom: "aQz".into(), rules: vec!["Q=QQ".into()], ..Source::default() }).unwrap();
    let s = derive(&g, 2, 0, &Limits::default()).unwrap();
    assert_eq!(s.syms, b"aQQQQz");
}

#[test]
fn parametric_rules_rewrite_with_conditions() {
    let g = Grammar::compile(&Source {
        axiom: "A(4)".into(),
        rules: vec!["A(x) : x > 1 -> F(x)[+A(x/2)]A(x-1)".into(), "A(x) : x <= 1 -> L".into()],
        ..Source::default()
    })
    .unwrap();
    let s = derive(&g, 1, 0, &Limits::default()).unwrap();
    assert_eq!(s.to_text(&g), "F(4)[+A(2)]A(3)");
    let s = derive(&g, 2, 0, &Limits::default()).unwrap();
    // A(2) -> F(2)[+A(1)]A(1); A(3) -> F(3)[+A(1.5)]A(2).
    assert_eq!(s.to_text(&g), "F(4)[+F(2)[+A(1)]A(1)]F(3)[+A(1.5)]A(2)");
    let s = derive(&g, 3, 0, &Limits::default()).unwrap();
    assert_eq!(s.to_text(&g), "F(4)[+F(2)[+L]L]F(3)[+F(1.5)[+A(0.75)]A(0.5)]F(2)[+A(1)]A(1)");
    // The parallel and sequential turtles agree on parametric strings too.
    let big = derive(&g, 12, 0, &Limits::default()).unwrap();
    assert_eq!(turtle::interpret(&big, &g).unwrap(), turtle::interpret_parallel(&big, &g, u64::MAX).unwrap());
    // ABOP's notation from the issue: F(l) -> F(l*0.8)[+F(l*0.6)].
    let g = Grammar::compile(&Source {
        axiom: "F(1)".into(),
        rules: vec!["F(l) -> F(l*0.8)[+F(l*0.6)]".into()],
        ..Source::default()
    })
    .unwrap();
    let s = derive(&g, 1, 0, &Limits::default()).unwrap();
    assert_eq!(s.params, vec![0.8, 0.6]);
    assert_eq!(s.syms, b"F[+F]");
}

#[test]
fn parallel_turtle_equals_sequential_turtle_on_every_preset() {
    let limits = Limits::default();
    for name in presets::names() {
        let g = presets::preset(name).unwrap();
        let mut n = g.n;
        while n > 1 && derive(&g, n, 3, &limits).unwrap().len() > 1_500_000 {
            n -= 1;
        }
        let s = derive(&g, n, 3, &limits).unwrap();
        let seq = turtle::interpret(&s, &g).unwrap();
        let par1 = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| turtle::interpret_parallel(&s, &g, u64::MAX))
            .unwrap();
        let par2 = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap()
            .install(|| turtle::interpret_parallel(&s, &g, u64::MAX))
            .unwrap();
        assert!(!seq.is_empty(), "{name}");
        assert_eq!(seq.len(), s.counts()[b'F' as usize] as usize, "{name}");
        assert!(seq == par1, "{name}: one-thread parallel turtle differs");
        assert!(seq == par2, "{name}: two-thread parallel turtle differs");
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn a_small_system_draws_the_segments_worked_out_by_hand() {
    // Angle 90°, step 1, width 0.2, width factor 0.5. The turtle starts at the origin heading +Y
    // with left = -X and up = +Z.
    // F        : (0,0,0) -> (0,1,0)
    // [+F]     : turn left (towards -X): (0,1,0) -> (-1,1,0), depth 1, branch 1
    // [-FF]    : turn right (towards +X): (0,1,0) -> (1,1,0) -> (2,1,0), depth 1, branch 2
    // !        : width 0.2 -> 0.1
    // &F       : pitch down (heading towards -Z): (0,1,0) -> (0,1,-1), width 0.1
    // |F       : turn around (heading +Z): (0,1,-1) -> (0,1,0)
    let g = Grammar::compile(&Source {
        axiom: "F[+F][-FF]!&F|F".into(),
        angle_deg: 90.0,
        width: 0.2,
        width_factor: 0.5,
        ..Source::default()
    })
    .unwrap();
    let s = derive(&g, 0, 0, &Limits::default()).unwrap();
    let segs = turtle::interpret(&s, &g).unwrap();
    let want = [
        (Vec3::ZERO, Vec3::Y, 0.2, 0, 0),
        (Vec3::Y, Vec3::new(-1.0, 1.0, 0.0), 0.2, 1, 1),
        (Vec3::Y, Vec3::new(1.0, 1.0, 0.0), 0.2, 1, 2),
        (Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 1.0, 0.0), 0.2, 1, 2),
        (Vec3::Y, Vec3::new(0.0, 1.0, -1.0), 0.1, 0, 0),
        (Vec3::new(0.0, 1.0, -1.0), Vec3::Y, 0.1, 0, 0),
    ];
    assert_eq!(segs.len(), want.len());
    for (i, (sg, w)) in segs.iter().zip(want).enumerate() {
        assert!(close(sg.start, w.0) && close(sg.end, w.1), "segment {i}: {sg:?} vs {w:?}");
        assert!((sg.width - w.2).abs() < 1e-7, "segment {i} width {}", sg.width);
        assert_eq!((sg.depth, sg.branch), (w.3, w.4), "segment {i}");
    }
    // Parametric forms: F(2), then +(90) turns towards -X, F(0.5), !(0.3) sets the width, F(1).
    let g =
        Grammar::compile(&Source { axiom: "F(2)+(90)F(0.5)!(0.3)F(1)".into(), angle_deg: 10.0, ..Source::default() })
            .unwrap();
    let segs = turtle::interpret(&derive(&g, 0, 0, &Limits::default()).unwrap(), &g).unwrap();
    assert_eq!(segs.len(), 3);
    assert!(close(segs[0].end, Vec3::new(0.0, 2.0, 0.0)), "{:?}", segs[0]);
    assert!(close(segs[1].end, Vec3::new(-0.5, 2.0, 0.0)), "{:?}", segs[1]);
    assert!(close(segs[2].end, Vec3::new(-1.5, 2.0, 0.0)) && segs[2].width == 0.3, "{:?}", segs[2]);
    // Roll: `/` turns left and up about the heading, so after `&` the heading is unchanged by it.
    let g = Grammar::compile(&Source { axiom: "+/F".into(), angle_deg: 90.0, ..Source::default() }).unwrap();
    let segs = turtle::interpret(&derive(&g, 0, 0, &Limits::default()).unwrap(), &g).unwrap();
    assert!(close(segs[0].end, Vec3::new(-1.0, 0.0, 0.0)), "{:?}", segs[0]);
}

#[test]
fn the_conifer_preset_has_thin_branches_with_needles_along_them() {
    // A conifer's branches leave the trunk at a fraction of its girth and carry twigs of needles
    // along their whole length: not planks as thick as the trunk with a tuft at their ends.
    let g = presets::preset("conifer").unwrap();
    let s = derive(&g, 8, 1, &Limits::default()).unwrap();
    let segs = turtle::interpret(&s, &g).unwrap();
    let trunk = segs.iter().filter(|s| s.depth == 0).map(|s| s.width).fold(0.0, f32::max);
    let branches: Vec<_> = segs.iter().filter(|s| s.depth == 1).collect();
    let thickest = branches.iter().map(|s| s.width).fold(0.0, f32::max);
    assert!(!branches.is_empty() && thickest <= 0.4 * trunk, "branches up to {thickest} wide on a trunk {trunk} wide");
    // Four twigs on each branch segment; the leader's own twigs, also one bracket deep, bring
    // the ratio down (two twigs a segment, as the conifer had, give 2 at most).
    let twigs = segs.iter().filter(|s| s.depth == 2).count();
    assert!(twigs as f32 >= 2.2 * branches.len() as f32, "{twigs} twigs on {} branch segments", branches.len());
}
