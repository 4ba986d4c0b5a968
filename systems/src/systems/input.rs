//! Input system: applies the tick's input events to the controller, the head and the UI state.
//!
//! Reads: `Resources::input` (drained), `Resources::mode`, `Resources::menu`.
//! Writes: `Controller` (pose, buttons, touchpad), `ScalePad` (added to the controller's entity by
//! the first `scale_axis` event), `Head` (pose), `Resources::edges`,
//! `Resources::mode`, `Resources::menu`, `Resources::interaction.pending_spawn`,
//! `Resources::task` (start, its targets laid out in a room when the event says so, and end),
//! `Resources::log` (mode_changed, menu_opened,
//! model_chosen, task_started, task_ended).

use hecs::World;

use crate::components::{Buttons, Controller, Head, ScalePad};
use crate::events::Happening;
use crate::input::{Button, InputEvent};
use crate::known_techniques::KnownTechniques as Techniques;
use crate::mode::Mode;
use crate::resources::{ButtonEdges, Resources};
use crate::single;

fn set(b: &mut Buttons, button: Button, value: bool) {
    match button {
        Button::Trigger => b.trigger = value,
        Button::Bumper => b.bumper = value,
        Button::Touchpad => b.touchpad = value,
        Button::Menu => b.menu = value,
    }
}

/// Runs the input system.
pub fn run(world: &mut World, res: &mut Resources) {
    res.edges = ButtonEdges::default();
    if res.input.is_empty() {
        return;
    }
    let tick = res.tick;
    let events = std::mem::take(&mut res.input);
    for event in &events {
        match event {
            InputEvent::ControllerPose { pose } => {
                single::for_each_mut::<Controller>(world, &res.singles, |c| c.pose = *pose);
            }
            InputEvent::HeadPose { pose } => {
                single::for_each_mut::<Head>(world, &res.singles, |h| h.pose = *pose);
            }
            InputEvent::ButtonDown { button } | InputEvent::ButtonUp { button } => {
                let down = matches!(event, InputEvent::ButtonDown { .. });
                single::for_each_mut::<Controller>(world, &res.singles, |c| set(&mut c.buttons, *button, down));
                if down {
                    set(&mut res.edges.down, *button, true);
                } else {
                    set(&mut res.edges.up, *button, true);
                }
                if down && *button == Button::Menu {
                    open_menu(res, tick);
                }
            }
            InputEvent::TouchpadAxes { axes } => {
                single::for_each_mut::<Controller>(world, &res.singles, |c| c.touchpad = *axes);
            }
            InputEvent::ScaleAxis { value } => scale_pad(world, res, *value),
            InputEvent::OpenMenu => open_menu(res, tick),
            InputEvent::CloseMenu => res.menu.open = false,
            InputEvent::ChooseModel { model } => {
                let Ok(model) = res.catalogue.resolve(model) else {
                    continue;
                };
                res.menu.current_model = model;
                res.log.push(tick, Happening::ModelChosen { model });
                // In manual mode a tree appears only when chosen from an open menu, and the
                // menu closes, so it must be reopened for every new tree.
                if res.mode == Mode::Manual && res.menu.open {
                    res.interaction.pending_spawn = Some(model);
                }
                res.menu.open = false;
            }
            InputEvent::SwitchMode { mode } => switch(res, tick, Techniques::of_mode(*mode)),
            InputEvent::SwitchTechnique { technique } => {
                // A name that is not registered changes nothing (a replay refuses it up front).
                if let Some(index) = res.techniques.index(technique) {
                    switch(res, tick, index);
                }
            }
            InputEvent::StartTask { task, layout } => {
                match crate::task::TaskDef::builtin(task) {
                    Some(def) => {
                        res.task = Some(crate::task::TaskState::laid_out(def, tick, layout.as_ref()));
                        res.log.push(tick, Happening::TaskStarted { task: task.clone() });
                    }
                    None => {
                        // An unknown task id is kept visible in the log but starts no clock.
                        res.log.push(tick, Happening::TaskStarted { task: format!("unknown:{task}") });
                    }
                }
            }
            InputEvent::EndTask => {
                if let Some(t) = res.task.as_mut() {
                    if t.ended_tick.is_none() {
                        t.ended_tick = Some(tick);
                        res.log.push(tick, Happening::TaskEnded);
                    }
                }
            }
        }
    }
    // Hand the allocation back so that steady-state ticks do not allocate.
    let mut events = events;
    events.clear();
    res.input = events;
}

/// Makes technique `index` the active one. Its base mode changes as a mode switch always did
/// (menu closed, no pending spawn, `ModeChanged` logged); a change to or from a plug-in
/// technique is logged as `TechniqueChanged`.
fn switch(res: &mut Resources, tick: u64, index: usize) {
    let mode = res.techniques.at(index).base;
    if res.mode != mode {
        res.mode = mode;
        res.menu.open = false;
        res.interaction.pending_spawn = None;
        res.log.push(tick, Happening::ModeChanged { mode });
    }
    if res.technique != index {
        let plug_in = !res.techniques.at(index).is_builtin() || !res.techniques.at(res.technique).is_builtin();
        res.technique = index;
        if plug_in {
            res.log.push(tick, Happening::TechniqueChanged { technique: res.techniques.at(index).name.to_string() });
        }
    }
}

/// Sets the Scale pad's value on the controller's entity, adding the pad on its first event.
fn scale_pad(world: &mut World, res: &Resources, value: f32) {
    let Some(e) = res.singles.entity::<Controller>() else { return };
    match world.query_one_mut::<&mut ScalePad>(e) {
        Ok(pad) => pad.value = value,
        Err(_) => {
            let _ = world.insert_one(e, ScalePad { value, gesture: None });
        }
    }
}

fn open_menu(res: &mut Resources, tick: u64) {
    if !res.menu.open {
        res.menu.open = true;
        res.log.push(tick, Happening::MenuOpened);
    }
}
