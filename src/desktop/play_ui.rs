//! The `grove play` user interface. [`PlayUi::ui`] draws one frame and returns the input events
//! the user's clicks mean; the app queues them like any other input, so UI actions are
//! recorded and replayed exactly like controller input.

use egui::{Color32, RichText, Ui};
use glam::Vec3;
use grove_systems::catalogue::{ModelId, ModelKind};
use grove_systems::components::{Pose, Transform, Tree};
use grove_systems::input::{Button, InputEvent};
use grove_systems::resources::Mode;
use grove_systems::task::{TaskDef, BUILTIN_TASKS};
use grove_systems::Sim;

use super::input_map::BINDINGS;

/// Numbers for the debug panel, measured by the app.
#[derive(Clone, Debug, Default)]
pub struct DebugStats {
    /// Frames per second, smoothed.
    pub fps: f32,
    /// The last frame's time, milliseconds.
    pub frame_ms: f32,
    /// The GPU adapter, e.g. "llvmpipe (LLVM 15.0.6) (Vulkan, Cpu)".
    pub adapter: String,
    /// Where the recording goes, if anywhere.
    pub recording: Option<String>,
}

/// Which screen is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Screen {
    /// The start menu: free planting or a study task.
    Start,
    /// The session itself.
    Session,
}

/// The state of the play UI.
pub struct PlayUi {
    /// The current screen.
    pub screen: Screen,
    /// Whether the help overlay is shown.
    pub show_help: bool,
    /// Whether the debug panel is shown.
    pub show_debug: bool,
    /// Whether the tree-selection window is shown.
    pub show_trees: bool,
    /// Measured numbers for the debug panel.
    pub stats: DebugStats,
    /// A thumbnail per model (by model index), once the renderer has drawn them.
    pub thumbnails: Vec<Option<egui::TextureId>>,
    /// The head pose "Reset view" returns to.
    pub home: Pose,
    /// Set when the user asked to quit.
    pub quit: bool,
}

impl PlayUi {
    /// A UI that starts on the start menu; `home` is the scene's camera pose.
    pub fn new(home: Pose) -> PlayUi {
        PlayUi { screen: Screen::Start, show_help: false, show_debug: true, show_trees: true, stats: DebugStats::default(), thumbnails: Vec::new(), home, quit: false }
    }

    /// The events that start a study task: its mode, then the task itself.
    pub fn start_task_events(id: &str) -> Vec<InputEvent> {
        let mode = TaskDef::builtin(id).map_or(Mode::RayCasting, |d| d.mode);
        vec![InputEvent::SwitchMode { mode }, InputEvent::StartTask { task: id.to_string() }]
    }

    /// The events that remove every tree: for each, the controller is put above its crown
    /// looking straight down and the Bumper is clicked, exactly as a user could do it.
    pub fn clear_events(sim: &Sim) -> Vec<InputEvent> {
        let mut trees: Vec<(u64, Vec3, f32)> = sim
            .world
            .query::<(hecs::Entity, &Tree, &Transform)>()
            .iter()
            .map(|(e, t, tf)| (e.to_bits().get(), tf.translation, sim.res.catalogue.get(t.model).map_or(1.0, |m| m.bounds_max.y)))
            .collect();
        trees.sort_by_key(|t| t.0);
        let mut out = Vec::new();
        for (_, base, top) in trees {
            let from = base + Vec3::Y * (top * 4.0 + 2.0);
            let pose = Pose::looking_at(from, base + Vec3::new(0.0, -1.0, 0.0));
            out.push(InputEvent::ControllerPose { pose });
            out.push(InputEvent::ButtonDown { button: Button::Bumper });
            out.push(InputEvent::ButtonUp { button: Button::Bumper });
        }
        out
    }

    /// Draws the UI for one frame over the world view and returns the events it produced.
    pub fn ui(&mut self, ui: &mut Ui, sim: &Sim) -> Vec<InputEvent> {
        let mut out = Vec::new();
        match self.screen {
            Screen::Start => self.start_menu(ui, &mut out),
            Screen::Session => {
                self.top_bar(ui, sim, &mut out);
                if self.show_trees || sim.res.menu.open {
                    self.tree_window(ui, sim, &mut out);
                }
                if sim.res.task.is_some() {
                    task_panel(ui, sim, &mut out, true);
                }
            }
        }
        if self.show_debug {
            self.debug_window(ui, sim);
        }
        if self.show_help {
            egui::Window::new("Help: key bindings").collapsible(false).open(&mut self.show_help).show(ui.ctx(), |ui| {
                egui::Grid::new("bindings").striped(true).show(ui, |ui| {
                    for (keys, action) in BINDINGS {
                        ui.label(RichText::new(*keys).strong());
                        ui.label(*action);
                        ui.end_row();
                    }
                });
            });
        }
        out
    }

    fn start_menu(&mut self, ui: &mut Ui, out: &mut Vec<InputEvent>) {
        egui::Window::new("grove").collapsible(false).resizable(false).anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0]).show(ui.ctx(), |ui| {
            ui.heading("Plant trees on the study site");
            ui.add_space(6.0);
            if ui.button("Free planting").clicked() {
                self.screen = Screen::Session;
            }
            ui.separator();
            ui.label("Run a study task:");
            for (id, _) in BUILTIN_TASKS {
                if ui.button(format!("Task {id}")).clicked() {
                    out.extend(PlayUi::start_task_events(id));
                    self.screen = Screen::Session;
                }
            }
            ui.separator();
            if ui.button("Help").clicked() {
                self.show_help = true;
            }
        });
    }

    fn top_bar(&mut self, ui: &mut Ui, sim: &Sim, out: &mut Vec<InputEvent>) {
        egui::Panel::top("top bar").show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label("Mode:");
                for mode in [Mode::RayCasting, Mode::Manual] {
                    let label = match mode {
                        Mode::RayCasting => "Ray-casting",
                        Mode::Manual => "Manual modification",
                    };
                    if ui.selectable_label(sim.res.mode == mode, label).clicked() && sim.res.mode != mode {
                        out.push(InputEvent::SwitchMode { mode });
                    }
                }
                ui.separator();
                ui.toggle_value(&mut self.show_trees, "Trees");
                if ui.button("Clear trees").clicked() {
                    out.extend(PlayUi::clear_events(sim));
                }
                if ui.button("Reset view").clicked() {
                    out.push(InputEvent::HeadPose { pose: self.home });
                }
                ui.separator();
                ui.toggle_value(&mut self.show_debug, "Debug");
                ui.toggle_value(&mut self.show_help, "Help");
                if ui.button("Quit").clicked() {
                    self.quit = true;
                }
                if let Some(path) = &self.stats.recording {
                    ui.label(RichText::new(format!("REC {path}")).color(Color32::from_rgb(220, 40, 40)));
                }
            });
        });
    }

    fn tree_window(&mut self, ui: &mut Ui, sim: &Sim, out: &mut Vec<InputEvent>) {
        let title = if sim.res.menu.open { "Trees (menu open)" } else { "Trees" };
        egui::Window::new(title).id(egui::Id::unique("trees window")).default_pos([10.0, 60.0]).resizable(false).show(ui.ctx(), |ui| {
            for (kind, heading) in [(ModelKind::Mesh, "Mesh"), (ModelKind::Billboard, "Billboard")] {
                ui.label(RichText::new(heading).strong());
                ui.horizontal_wrapped(|ui| {
                    for i in 0..sim.res.catalogue.len() {
                        let id = ModelId(i as u8);
                        let Some(m) = sim.res.catalogue.get(id) else { continue };
                        if m.kind != kind {
                            continue;
                        }
                        let current = sim.res.menu.current_model == id;
                        let thumb = self.thumbnails.get(i).copied().flatten();
                        let button = match thumb {
                            Some(tex) => egui::Button::image_and_text(egui::Image::new((tex, egui::vec2(64.0, 64.0))), m.name.as_str()),
                            None => egui::Button::new(m.name.as_str()),
                        };
                        if ui.add(button.selected(current)).clicked() {
                            if sim.res.mode == Mode::Manual && !sim.res.menu.open {
                                out.push(InputEvent::OpenMenu);
                            }
                            out.push(InputEvent::ChooseModel { model: id });
                        }
                    }
                });
            }
            if sim.res.menu.open && ui.button("Close menu").clicked() {
                out.push(InputEvent::CloseMenu);
            }
        });
    }

    fn debug_window(&mut self, ui: &mut Ui, sim: &Sim) {
        egui::Window::new("Debug").default_pos([1000.0, 60.0]).resizable(false).show(ui.ctx(), |ui| {
            let c = sim.counts();
            ui.label(format!("fps {:.0}, frame {:.1} ms", self.stats.fps, self.stats.frame_ms));
            ui.label(format!("tick {} ({:.2} s)", sim.res.tick, sim.res.time()));
            ui.label(format!("entities {}: {} trees, {} planes", c.total, c.trees, c.planes));
            ui.label(format!("mode {}, model {}", sim.res.mode.name(), sim.res.catalogue.get(sim.res.menu.current_model).map_or("?", |m| m.name.as_str())));
            ui.label(format!("GPU {}", if self.stats.adapter.is_empty() { "none" } else { &self.stats.adapter }));
        });
    }
}

/// The task panel: targets with check marks and per-tree times, the running timer, and (when
/// `interactive`) the finish button.
pub fn task_panel(ui: &mut Ui, sim: &Sim, out: &mut Vec<InputEvent>, interactive: bool) {
    let Some(task) = sim.res.task.as_ref() else { return };
    egui::Panel::right("task panel").resizable(false).show(ui, |ui| {
        ui.heading(format!("Task {}", task.def.id));
        let end = task.completed_tick.or(task.ended_tick).unwrap_or(sim.res.tick);
        let secs = end.saturating_sub(task.started_tick) as f64 * sim.res.dt as f64;
        ui.label(RichText::new(format!("time {secs:.1} s")).monospace().size(18.0));
        if task.is_complete() {
            ui.label(RichText::new("all targets done").color(Color32::from_rgb(40, 200, 90)));
        }
        ui.separator();
        for (i, t) in task.def.targets.iter().enumerate() {
            let hit = task.satisfied.get(i).copied().flatten();
            let mark = if hit.is_some() { "[x]" } else { "[ ]" };
            let time = hit.map(|h| format!(" {:.1} s", (h.tick - task.started_tick) as f64 * sim.res.dt as f64)).unwrap_or_default();
            ui.label(format!("{mark} {} at ({:.1}, {:.1}){time}", t.model, t.position.x, t.position.z));
        }
        ui.separator();
        ui.label(format!("errors {}", task.errors.total()));
        if interactive && task.ended_tick.is_none() && ui.button("Finish task").clicked() {
            out.push(InputEvent::EndTask);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui_kittest::kittest::Queryable;
    use egui_kittest::Harness;
    use grove_systems::scene::Scene;

    use crate::desktop::session::LiveSession;

    /// The play UI and a live session, as the app holds them.
    struct App {
        ui: PlayUi,
        session: LiveSession,
    }

    fn harness() -> Harness<'static, App> {
        let sim = Sim::from_scene(&Scene::builtin("study").unwrap(), 3).unwrap();
        let home = crate::desktop::world_view::head_of(&sim).pose;
        let app = App { ui: PlayUi::new(home), session: LiveSession::new(sim, None) };
        Harness::builder().with_size(egui::vec2(1280.0, 720.0)).build_ui_state(
            |ui, app: &mut App| {
                for e in app.ui.ui(ui, &app.session.sim) {
                    app.session.queue(e).unwrap();
                }
            },
            app,
        )
    }

    /// Steps the session until its queued input has been applied.
    fn settle(h: &mut Harness<'static, App>) {
        h.run();
        let s = &mut h.state_mut().session;
        for _ in 0..3 {
            s.step(0).unwrap();
        }
        h.run();
    }

    #[test]
    fn choosing_a_model_and_planting_it() {
        let mut h = harness();
        h.get_by_label("Free planting").click();
        h.run();
        assert_eq!(h.state().ui.screen, Screen::Session);
        h.get_by_label("birch-billboard").click();
        settle(&mut h);
        let sim = &h.state().session.sim;
        let birch = sim.res.catalogue.by_name("birch-billboard").unwrap().id;
        assert_eq!(sim.res.menu.current_model, birch);

        // Plant it with the controller: aim at the ground in front and click.
        let s = &mut h.state_mut().session;
        let pose = Pose::looking_at(Vec3::new(0.0, 1.7, 6.0), Vec3::new(1.0, 0.0, 1.0));
        s.queue(InputEvent::ControllerPose { pose }).unwrap();
        s.queue(InputEvent::ButtonDown { button: Button::Trigger }).unwrap();
        s.queue(InputEvent::ButtonUp { button: Button::Trigger }).unwrap();
        settle(&mut h);
        let sim = &h.state().session.sim;
        let planted: Vec<ModelId> = sim.world.query::<&Tree>().iter().map(|t| t.model).filter(|m| *m == birch).collect();
        assert_eq!(planted.len(), 1, "one birch billboard was planted");

        // Clear removes every tree through Bumper clicks.
        assert!(sim.counts().trees >= 3);
        h.get_by_label("Clear trees").click();
        h.run();
        let s = &mut h.state_mut().session;
        while s.pending_ticks() > 0 {
            s.step(0).unwrap();
        }
        s.step(0).unwrap();
        assert_eq!(s.sim.counts().trees, 0);
    }

    #[test]
    fn switching_mode_and_choosing_from_the_menu_spawns_a_tree() {
        let mut h = harness();
        h.get_by_label("Free planting").click();
        h.run();
        h.get_by_label("Manual modification").click();
        settle(&mut h);
        assert_eq!(h.state().session.sim.res.mode, Mode::Manual);
        let before = h.state().session.sim.counts().trees;
        h.get_by_label("conifer-mesh").click();
        settle(&mut h);
        let sim = &h.state().session.sim;
        assert_eq!(sim.counts().trees, before + 1, "manual mode: choosing from the menu spawns a tree");
        assert_eq!(sim.res.log.count("menu_opened"), 1);
    }

    #[test]
    fn starting_a_task_shows_its_targets_and_timer() {
        let mut h = harness();
        h.get_by_label("Task manual-7").click();
        settle(&mut h);
        {
            let sim = &h.state().session.sim;
            let task = sim.res.task.as_ref().expect("the task started");
            assert_eq!(task.def.id, "manual-7");
            assert_eq!(sim.res.mode, Mode::Manual);
        }
        for _ in 0..60 {
            h.state_mut().session.step(0).unwrap();
        }
        h.run();
        h.get_by_label("Task manual-7");
        assert_eq!(h.query_all_by_label_contains("[ ]").count(), 7, "seven unchecked targets");
        let t = h.query_by_label_contains("time ").expect("a task timer");
        let secs: f64 = t.value().unwrap().trim_start_matches("time ").trim_end_matches(" s").parse().unwrap();
        assert!(secs >= 1.0, "the timer runs: {secs}");
        h.get_by_label("Finish task").click();
        settle(&mut h);
        assert!(h.state().session.sim.res.task.as_ref().unwrap().ended_tick.is_some());
    }

    #[test]
    fn the_help_overlay_lists_the_bindings() {
        let mut h = harness();
        h.get_by_label("Help").click();
        h.run();
        h.get_by_label("Tab or M");
        h.get_by_label("Right button");
        assert!(h.state().ui.show_help);
    }
}
