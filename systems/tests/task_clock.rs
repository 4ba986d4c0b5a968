//! The task clock stops when the task ends (every target satisfied, or the participant's
//! EndTask), never at the end of the input, and nothing after the end counts as an error.

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::input::Button;
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::task::TaskReport;

fn study() -> Script {
    Script::new(Sim::from_scene(&Scene::builtin("study").unwrap(), 7).unwrap())
}

/// The report as `grove replay` and `grove study` build it, with "now" the last tick run.
fn report(s: &Script) -> TaskReport {
    let sim = s.sim();
    TaskReport::new(sim.task().unwrap(), sim.dt(), sim.tick(), sim.catalogue())
}

#[test]
fn an_ended_task_is_timed_at_its_end_task_not_at_the_end_of_the_input() {
    let mut s = study();
    s.wait(5).start_task("ray-casting-7");
    let started = s.sim().task().unwrap().started_tick;
    s.wait(200);
    let end_tick = s.sim().tick();
    s.end_task();
    let dt = s.sim().dt() as f64;
    let at_end = report(&s);
    // Long after the end, the participant (or a script) keeps clicking at the ground far from
    // every target: planting there would be an off-target error during the task.
    s.point_at(Vec3::new(14.0, 0.0, 5.0)).press(Button::Trigger).wait(500);
    let later = report(&s);
    // The study runs at 60 ticks a second: times are whole ticks over 60, exactly.
    assert!((dt - 1.0 / 60.0).abs() < 1e-6);
    let expected = (end_tick - started) as f64 / 60.0;
    assert!((at_end.time_s - expected).abs() < 1e-9, "{} vs {expected}", at_end.time_s);
    assert_eq!(later.time_s, at_end.time_s, "the clock stopped at EndTask");
    assert!(!later.completed);
    assert_eq!(later.errors, 0, "what happens after the end is not part of the task");
    assert!(s.sim().counts().trees > 2, "the click after the end did plant a tree");
}

#[test]
fn a_running_task_is_timed_up_to_now() {
    let mut s = study();
    s.start_task("ray-casting-7").wait(100);
    let task = s.sim().task().unwrap();
    assert!(task.end_tick().is_none());
    let expected = (s.sim().tick() - task.started_tick) as f64 / 60.0;
    assert!((report(&s).time_s - expected).abs() < 1e-9);
}
