//! The wind and sun systems inside a running simulation: determinism, per-tree variety, gust
//! periodicity, gain updates when a tree moves, the bend bound and the sun's clock.

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::components::{Transform, WindState};
use grove_systems::scene::Scene;
use grove_systems::systems::wind::{det_sin, gust_at, max_bend, position_gain};

fn scene() -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/scenes/study.ron");
    Scene::load(std::path::Path::new(path)).expect("study scene loads")
}

fn sim_with_trees(n: usize) -> Sim {
    let scene = scene();
    let mut sim = Sim::from_scene(&scene, scene.seed).unwrap();
    sim.scatter_trees(n);
    sim
}

fn states(sim: &Sim) -> Vec<WindState> {
    let mut v: Vec<(u64, WindState)> = Vec::new();
    sim.for_each_tree(|t| v.extend(t.wind.map(|w| (t.id, w))));
    v.sort_by_key(|(e, _)| *e);
    v.into_iter().map(|(_, w)| w).collect()
}

#[test]
fn wind_is_deterministic_and_part_of_the_world_hash() {
    let mut a = sim_with_trees(300);
    let mut b = sim_with_trees(300);
    a.run(240);
    b.run(240);
    assert_eq!(a.hash(), b.hash());
    // The wind state changes from tick to tick, and the hash sees it.
    let before = a.hash().component("WindState").unwrap();
    a.run(7);
    assert_ne!(a.hash().component("WindState").unwrap(), before);
    assert_ne!(a.hash().component("Wind").unwrap(), b.hash().component("Wind").unwrap());
}

#[test]
fn trees_at_different_positions_get_different_gains_and_bends() {
    let mut sim = sim_with_trees(400);
    sim.run(31);
    let s = states(&sim);
    assert!(s.len() >= 400);
    let mut gains: Vec<f32> = s.iter().map(|w| w.gain).collect();
    gains.sort_by(f32::total_cmp);
    gains.dedup();
    assert!(gains.len() > 350, "only {} distinct gains", gains.len());
    assert!(gains.first().unwrap() >= &0.5 && gains.last().unwrap() <= &1.5);
    assert!(gains.last().unwrap() - gains.first().unwrap() > 0.3, "gains span too little: {gains:?}");
    // Bends are not one bend scaled by the gain: the trees' phases differ too.
    let ratios: Vec<f32> = s.iter().map(|w| w.bend.length() / w.gain).collect();
    let (lo, hi) = ratios.iter().fold((f32::MAX, f32::MIN), |(l, h), r| (l.min(*r), h.max(*r)));
    assert!(hi - lo > 0.1 * hi, "bends move in lockstep: {lo}..{hi}");
    // And every bend points along the wind.
    let w = sim.wind().unwrap();
    for ws in &s {
        assert!((ws.bend.x * w.direction.z - ws.bend.y * w.direction.x).abs() < 1e-6);
    }
}

#[test]
fn gust_is_periodic_and_stays_within_its_range() {
    let w = sim_with_trees(0).wind().unwrap();
    let g = w.gust;
    let period = 1.0 / g.frequency as f64;
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for i in 0..2000 {
        let t = i as f64 * 0.037;
        let a = gust_at(&g, t);
        assert!((a - gust_at(&g, t + period)).abs() < 1e-4, "not periodic at t = {t}");
        assert!((a - gust_at(&g, t + 7.0 * period)).abs() < 1e-4);
        assert!(a >= g.average - g.strength - 1e-6 && a <= g.average + g.strength + 1e-6);
        lo = lo.min(a);
        hi = hi.max(a);
    }
    // The shape uses most of its amplitude.
    assert!(hi - lo > 1.2 * g.strength, "gust spans only {lo}..{hi}");
    // Not constant within a period.
    assert!((gust_at(&g, 0.25 * period) - gust_at(&g, 0.75 * period)).abs() > 0.1 * g.strength);
    // The system writes the gust of the tick's time.
    let mut sim = sim_with_trees(1);
    sim.run(100);
    sim.step();
    let expected = gust_at(&g, 100.0 * sim.dt() as f64);
    assert_eq!(sim.wind().unwrap().current, expected);
}

#[test]
fn moving_a_tree_recomputes_its_gain() {
    let mut sim = sim_with_trees(5);
    sim.step();
    let id = sim.tree_ids()[0];
    let entity = hecs::Entity::from_bits(id).unwrap();
    let new_pos = Vec3::new(7.3, 0.0, -2.9);
    let moved = Transform { translation: new_pos, ..sim.tree(id).unwrap().transform };
    sim.set_up().transform(entity, moved).unwrap();
    sim.step();
    let density = sim.wind().unwrap().density;
    let ws = sim.tree_view(id).unwrap().wind.unwrap();
    assert_eq!(ws.gain, position_gain(new_pos, density));
    // So does changing the wind's density.
    let mut w = sim.wind().unwrap();
    w.density *= 3.0;
    sim.set_up().wind(w);
    sim.step();
    let ws = sim.tree_view(id).unwrap().wind.unwrap();
    assert_eq!(ws.gain, position_gain(new_pos, density * 3.0));
}

#[test]
fn bends_never_exceed_max_bend() {
    let mut sim = sim_with_trees(200);
    let bound = max_bend(&sim.wind().unwrap());
    let mut largest = 0.0f32;
    for _ in 0..40 {
        sim.run(17);
        for ws in states(&sim) {
            largest = largest.max(ws.bend.length());
            assert!(ws.bend.length() <= bound, "{} > {bound}", ws.bend.length());
        }
    }
    assert!(largest > 0.5 * bound, "largest bend {largest} vs bound {bound}");
}

#[test]
fn det_sin_is_accurate() {
    for i in -5000..5000 {
        let x = i as f32 * 0.01337;
        let err = (det_sin(x) as f64 - (x as f64).sin()).abs();
        assert!(err < 2e-5, "det_sin({x}) error {err}");
    }
}

#[test]
fn sun_clock_advances_at_its_time_rate() {
    let mut scene = scene();
    scene.sun.time_rate = 60.0;
    let mut sim = Sim::from_scene(&scene, scene.seed).unwrap();
    let start = sim.sun().unwrap();
    // 600 ticks of 1/60 s at 60 sun-seconds per second: ten sun-minutes.
    sim.run(600);
    let now = sim.sun().unwrap();
    assert_eq!(now.utc_ms - start.utc_ms, 600_000);
    assert!(now.azimuth_deg != start.azimuth_deg && now.elevation_deg != start.elevation_deg);
    let expected = grove_systems::systems::sun::sun_position(now.latitude_deg, now.longitude_deg, now.utc_ms).unwrap();
    assert_eq!(now.elevation_deg, expected.elevation_deg);
}

#[test]
fn scenes_choose_the_wind_model_and_response() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/scenes/study.ron");
    let text = std::fs::read_to_string(path).unwrap();
    let with = |extra: &str| text.replacen("gust_frequency: 0.2,", &format!("gust_frequency: 0.2, {extra}"), 1);
    let scene = Scene::parse(&with("model: noise, response: (trunk_stiffness: 7.5),"), "test").unwrap();
    let sim = Sim::from_scene(&scene, 1).unwrap();
    let w = sim.wind().unwrap();
    assert_eq!(w.model, grove_systems::wind_model::WindModel::Noise);
    assert_eq!(w.response.trunk_stiffness, 7.5);
    assert_eq!(w.response.leaf_frequency, grove_systems::wind_model::WindResponse::default().leaf_frequency);
    // The default is the hierarchical model.
    assert_eq!(
        Sim::from_scene(&self::scene(), 1).unwrap().wind().unwrap().model,
        grove_systems::wind_model::WindModel::Hierarchical
    );
    let err = Scene::parse(&with("response: (branch_stiffness: 0.0),"), "test").unwrap_err().to_string();
    assert!(err.contains("stiffness"), "{err}");
    assert!(Scene::parse(&with("response: (stifness: 1.0),"), "test").is_err());
}
