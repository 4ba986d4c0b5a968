//! The schedule: the one place that says which systems run, and in which order.
//!
//! One call of [`step`] is one fixed step of `Resources::dt` seconds:
//!
//! 1. `input`: apply this tick's input events to the controller, head, buttons and UI state.
//! 2. `sun`: advance the sun's clock and direction.
//! 3. `wind`: advance the gust and every tree's bend.
//! 4. `raycast`: cast the controller ray; move the hit marker to the nearest hit.
//! 5. `spawn`: in manual mode, a model chosen from the menu appears in front of the head.
//! 6. `plant_remove`: Trigger on a plane plants (ray-casting mode); Bumper on a tree removes it.
//! 7. `select`: Trigger on a tree selects and grabs it, on a handle grabs the handle, on empty
//!    ground deselects.
//! 8. `handles`: a grabbed corner handle scales, an edge handle rotates the selected tree.
//! 9. `touchpad`: moves and turns the selected tree.
//! 10. `scale_pad`: the Scale pad grows or shrinks the selected tree.
//! 11. `drag`: a grabbed tree follows the ray; the anchor ball; snap on release.
//! 12. `selection_box`: keep the selection box on the selected tree.
//! 13. `task`: check targets and measure the running task.
//!
//! The systems are grouped into named stages ([`Stage`]): `input` (1), `environment` (2–3), `ray`
//! (4), `interaction` (5–10), `constraints` (11–12) and `task` (13). The active technique's own
//! systems ([`crate::technique::Technique::systems`]) run after the built-in systems of their
//! stage; the two built-in techniques have none, so their order is exactly the list above.
//!
//! Then the tick counter advances. Systems run one after another on one thread; nothing in a
//! tick depends on thread timing or the wall clock.

use hecs::World;

use crate::resources::Resources;
use crate::systems;
use crate::technique::Techniques;
pub use crate::technique::{Stage, System};

/// The built-in systems with their stage and name, in the order they run.
pub const BUILTIN: &[(Stage, &str, System)] = &[
    (Stage::Input, "input", systems::input::run),
    (Stage::Environment, "sun", systems::sun::run),
    (Stage::Environment, "wind", systems::wind::run),
    (Stage::Ray, "raycast", systems::raycast::run),
    (Stage::Interaction, "spawn", systems::spawn::run),
    (Stage::Interaction, "plant_remove", systems::plant_remove::run),
    (Stage::Interaction, "select", systems::select::run),
    (Stage::Interaction, "handles", systems::handles::run),
    (Stage::Interaction, "touchpad", systems::touchpad::run),
    (Stage::Interaction, "scale_pad", systems::scale_pad::run),
    (Stage::Constraints, "drag", systems::drag::run),
    (Stage::Constraints, "selection_box", systems::selection_box::run),
    (Stage::Task, "task", systems::task::run),
];

/// Where each stage's built-in systems end in [`BUILTIN`] (they are grouped by stage, in order).
const STAGE_ENDS: [usize; Stage::ALL.len()] = {
    let mut ends = [0; Stage::ALL.len()];
    let mut k = 0;
    while k < Stage::ALL.len() {
        let mut i = 0;
        while i < BUILTIN.len() {
            if BUILTIN[i].0 as usize <= Stage::ALL[k] as usize {
                ends[k] = i + 1;
            }
            i += 1;
        }
        k += 1;
    }
    ends
};

/// Runs one fixed step: stage by stage, the built-in systems of the stage and then the active
/// technique's systems of that stage, then `tick += 1`.
pub fn step(world: &mut World, res: &mut Resources, techniques: &Techniques) {
    // The active technique is read once per stage: the input stage may switch it, and the new
    // technique's systems run from the next stage on.
    // The single components read or written by one system are kept for the next ones, within
    // this step only, and forgotten after each plug-in system ([`crate::single`]).
    res.singles.begin_step();
    let mut start = 0;
    for (stage, end) in Stage::ALL.into_iter().zip(STAGE_ENDS) {
        for (_, _, run) in &BUILTIN[start..end] {
            run(world, res);
        }
        start = end;
        let technique = techniques.at(res.technique);
        if technique.systems.is_empty() {
            continue;
        }
        let own: Vec<System> =
            technique.systems.iter().filter(|(s, _, _)| *s == stage).map(|(_, _, run)| *run).collect();
        for run in own {
            run(world, res);
            res.singles.forget();
        }
    }
    res.singles.end_step();
    res.tick += 1;
}

/// The systems a step runs with a technique active, as `(stage, name)` in order.
pub fn order(technique: &crate::technique::Technique) -> Vec<(Stage, &'static str)> {
    let mut out = Vec::new();
    for stage in Stage::ALL {
        out.extend(BUILTIN.iter().filter(|(s, _, _)| *s == stage).map(|(s, n, _)| (*s, *n)));
        out.extend(technique.systems.iter().filter(|(s, _, _)| *s == stage).map(|(s, n, _)| (*s, *n)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_order_is_the_documented_list() {
        let names: Vec<&str> = order(&crate::technique::Technique::ray_casting()).into_iter().map(|(_, n)| n).collect();
        assert_eq!(
            names,
            [
                "input",
                "sun",
                "wind",
                "raycast",
                "spawn",
                "plant_remove",
                "select",
                "handles",
                "touchpad",
                "scale_pad",
                "drag",
                "selection_box",
                "task"
            ]
        );
        // The stages are contiguous and in order, and each stage's systems end where
        // `STAGE_ENDS` says.
        assert!(BUILTIN.windows(2).all(|w| w[0].0 <= w[1].0));
        let mut start = 0;
        for (stage, end) in Stage::ALL.into_iter().zip(STAGE_ENDS) {
            assert!(BUILTIN[start..end].iter().all(|(s, _, _)| *s == stage), "{stage:?}");
            assert!(BUILTIN[end..].iter().all(|(s, _, _)| *s != stage), "{stage:?}");
            start = end;
        }
        assert_eq!(start, BUILTIN.len());
    }

    #[test]
    fn a_plug_in_system_runs_after_the_built_in_systems_of_its_stage() {
        fn mine(_: &mut World, _: &mut Resources) {}
        let mut t = crate::technique::Technique::ray_casting();
        t.systems.push((Stage::Ray, "mine", mine));
        let names: Vec<&str> = order(&t).into_iter().map(|(_, n)| n).collect();
        assert_eq!(&names[3..6], ["raycast", "mine", "spawn"]);
    }
}
