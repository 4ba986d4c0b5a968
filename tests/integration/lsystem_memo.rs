//! The memoised turtle: the same segments as the sequential turtle on every deterministic preset
//! (order, depth, branch and width exactly; positions within a stated tolerance), a small
//! system's segments worked out by hand, and a clear refusal of grammars it cannot memoise.

use glam::Vec3;
use grove::lsystem::grammar::Source;
use grove::lsystem::{Grammar, Limits, derive, memo, presets, turtle};

/// Positions may differ from the sequential turtle's by rounding only: at most this fraction of
/// the tree's extent (single precision carries about 7 digits; composing rotations in another
/// order loses a few of them over thousands of turns).
const TOLERANCE: f32 = 1e-5;

#[test]
fn memoised_turtle_equals_sequential_turtle_on_every_deterministic_preset() {
    let limits = Limits::default();
    let mut checked = 0;
    for name in presets::names() {
        let g = presets::preset(name).unwrap();
        if !memo::applies(&g) {
            continue;
        }
        let mut n = g.n;
        while n > 1 && derive(&g, n, 3, &limits).unwrap().len() > 500_000 {
            n -= 1;
        }
        let seq = turtle::interpret(&derive(&g, n, 3, &limits).unwrap(), &g).unwrap();
        let extent = seq.iter().map(|s| s.end.abs().max_element()).fold(g.step, f32::max);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mem = pool.install(|| memo::interpret_memo(&g, n, u64::MAX)).unwrap();
            assert_eq!(mem.len(), seq.len(), "{name} n = {n}");
            for (i, (a, b)) in seq.iter().zip(&mem).enumerate() {
                let d = (a.start - b.start).length().max((a.end - b.end).length());
                assert!(d <= TOLERANCE * extent, "{name} n = {n}, segment {i}: {a:?} vs {b:?}");
                assert_eq!((a.depth, a.branch), (b.depth, b.branch), "{name} n = {n}, segment {i}");
                assert!((a.width - b.width).abs() <= 1e-6 * a.width, "{name} n = {n}, segment {i}: width");
            }
        }
        checked += 1;
    }
    // Bourke's three bushes and ABOP Fig. 1.24 a-f are deterministic and free of parameters.
    assert!(checked >= 9, "only {checked} presets were memoisable");
}

#[test]
fn a_small_system_memoised_gives_the_segments_worked_out_by_hand() {
    // Angle 90°, step 1. Axiom A, rule A -> F[+F]A: after two steps the string is
    // F[+F]F[+F]A, drawn from the origin heading +Y with left = -X:
    // F (0,0,0)->(0,1,0); [+F] (0,1,0)->(-1,1,0) in branch 1; F (0,1,0)->(0,2,0);
    // [+F] (0,2,0)->(-1,2,0) in branch 2.
    let g = Grammar::compile(&Source {
        axiom: "A".into(),
        rules: vec!["A -> F[+F]A".into()],
        angle_deg: 90.0,
        ..Source::default()
    })
    .unwrap();
    let segs = memo::interpret_memo(&g, 2, u64::MAX).unwrap();
    let want = [
        (Vec3::ZERO, Vec3::Y, 0, 0),
        (Vec3::Y, Vec3::new(-1.0, 1.0, 0.0), 1, 1),
        (Vec3::Y, Vec3::new(0.0, 2.0, 0.0), 0, 0),
        (Vec3::new(0.0, 2.0, 0.0), Vec3::new(-1.0, 2.0, 0.0), 1, 2),
    ];
    assert_eq!(segs.len(), want.len());
    for (i, (s, w)) in segs.iter().zip(want).enumerate() {
        assert!((s.start - w.0).length() < 1e-6 && (s.end - w.1).length() < 1e-6, "segment {i}: {s:?}");
        assert_eq!((s.depth, s.branch), (w.2, w.3), "segment {i}");
    }
}

#[test]
fn grammars_that_cannot_be_memoised_are_refused_in_one_line() {
    let stochastic = Grammar::compile(&Source {
        axiom: "A".into(),
        rules: vec!["A -(1)-> FA".into(), "A -(1)-> F".into()],
        ..Source::default()
    })
    .unwrap();
    let parametric = Grammar::compile(&Source {
        axiom: "F(1)".into(),
        rules: vec!["F(l) -> F(l*0.8)[+F(l*0.6)]".into()],
        ..Source::default()
    })
    .unwrap();
    let unbalanced = Grammar::compile(&Source {
        axiom: "A[]".into(),
        rules: vec!["A -> F[A".into(), "B -> ]".into()],
        ..Source::default()
    });
    for g in [Some(stochastic), Some(parametric), unbalanced.ok()].into_iter().flatten() {
        assert!(!memo::applies(&g));
        let e = memo::interpret_memo(&g, 3, u64::MAX).unwrap_err().to_string();
        assert!(!e.contains('\n') && e.contains("memoised turtle"), "{e}");
    }
}

#[test]
fn a_memoised_interpretation_over_the_byte_limit_stops_with_one_line() {
    let g = presets::preset("bush2").unwrap();
    // Bush 2 at n = 8 draws 8^8 = 16,777,216 segments: far over 1 MB.
    let e = memo::interpret_memo(&g, 8, 1 << 20).unwrap_err().to_string();
    assert!(!e.contains('\n') && e.contains("bytes"), "{e}");
}
