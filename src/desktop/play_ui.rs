//! The `grove play` user interface. [`PlayUi::ui`] draws one frame and returns the input events
//! the user's clicks mean; the app queues them like any other input, so UI actions are
//! recorded and replayed exactly like controller input.

use egui::{Color32, RichText, Ui};
use glam::Vec3;
use grove_systems::catalogue::ModelKind;
use grove_systems::components::Pose;
use grove_systems::input::{Button, InputEvent};
use grove_systems::resources::Mode;
use grove_systems::task::{TaskDef, TaskReport, BUILTIN_TASKS};
use grove_systems::Sim;

use super::input_map::BINDINGS;

/// Numbers for the debug panel, measured by the app.
#[derive(Clone, Debug, Default)]
pub struct DebugStats {
    /// Frames per second over a rolling window of one second.
    pub fps: f32,
    /// The mean frame time over the same window, milliseconds.
    pub frame_ms: f32,
    /// Simulation ticks run per wall-clock second, over a rolling window of one second.
    pub ticks_per_s: f32,
    /// The 3D view's internal size and the window's size, pixels, when the renderer drew.
    pub view_size: Option<((u32, u32), (u32, u32))>,
    /// Whether the frame-time budget turned the shadows off.
    pub shadows_off: bool,
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
    /// Set when the user asked to quit (and confirmed, where that is needed).
    pub quit: bool,
    /// Whether the quit confirmation is shown.
    pub confirm_quit: bool,
}

/// The task's outcome as `grove replay` and `grove study` report it, computed the same way
/// ([`TaskReport::new`]) from the live world: "now" is the current tick, which only counts for a
/// task whose clock has not stopped yet.
pub fn task_result(sim: &Sim) -> Option<TaskReport> {
    sim.task().map(|t| TaskReport::new(t, sim.dt(), sim.tick(), sim.catalogue()))
}

/// A task result as one line, in the words of `grove replay`'s summary.
pub fn result_line(r: &TaskReport) -> String {
    r.result_line()
}

impl PlayUi {
    /// A UI that starts on the start menu; `home` is the scene's camera pose.
    pub fn new(home: Pose) -> PlayUi {
        PlayUi {
            screen: Screen::Start,
            show_help: false,
            show_debug: true,
            show_trees: true,
            stats: DebugStats::default(),
            thumbnails: Vec::new(),
            home,
            quit: false,
            confirm_quit: false,
        }
    }

    /// Whether quitting now needs a confirmation: during a running task or a recording.
    pub fn needs_confirmation(&self, sim: Option<&Sim>) -> bool {
        let task_running = sim.is_some_and(|s| s.task().is_some_and(|t| !t.is_over()));
        self.screen == Screen::Session && (task_running || self.stats.recording.is_some())
    }

    /// The user asked to quit (Escape, the Quit button or the window's close button): quit at
    /// once, or ask first (see [`PlayUi::needs_confirmation`]).
    pub fn request_quit(&mut self, sim: Option<&Sim>) {
        if self.needs_confirmation(sim) {
            self.confirm_quit = true;
        } else {
            self.quit = true;
        }
    }

    /// The events that start a study task: its mode, then the task itself.
    pub fn start_task_events(id: &str) -> Vec<InputEvent> {
        let mode = TaskDef::builtin(id).map_or(Mode::RayCasting, |d| d.mode);
        vec![InputEvent::SwitchMode { mode }, InputEvent::StartTask { task: id.to_string(), layout: None }]
    }

    /// The events that remove every tree: for each, the controller is put above its crown
    /// looking straight down and the Bumper is clicked, exactly as a user could do it.
    pub fn clear_events(sim: &Sim) -> Vec<InputEvent> {
        let mut trees: Vec<(u64, Vec3, f32)> = Vec::new();
        sim.for_each_tree(|v| trees.push((v.id, v.transform.translation, sim.catalogue().get(v.model).map_or(1.0, |m| m.bounds_max.y))));
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
                if self.show_trees || sim.menu().open {
                    self.tree_window(ui, sim, &mut out);
                }
                if sim.task().is_some() {
                    task_panel(ui, sim, &mut out, true);
                }
                if let Some(r) = task_result(sim).filter(|_| sim.task().is_some_and(|t| t.is_over())) {
                    result_window(ui, &r, sim);
                }
            }
        }
        if self.confirm_quit {
            self.quit_dialog(ui, sim);
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
                    let index = grove_systems::technique::Techniques::of_mode(mode);
                    if ui.selectable_label(sim.technique_index() == index, label).on_hover_text(technique_help(mode.name())).clicked() && sim.technique_index() != index {
                        out.push(InputEvent::SwitchMode { mode });
                    }
                }
                // The registered plug-in techniques (`src/techniques.rs`), by name.
                for (index, t) in sim.known_techniques().iter().enumerate().filter(|(_, t)| !t.is_builtin()) {
                    if ui.selectable_label(sim.technique_index() == index, t.name).on_hover_text(technique_help(t.name)).clicked() && sim.technique_index() != index {
                        out.push(InputEvent::SwitchTechnique { technique: t.name.to_string() });
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
                    self.request_quit(Some(sim));
                }
                if let Some(path) = &self.stats.recording {
                    ui.label(RichText::new(format!("REC {path}")).color(Color32::from_rgb(220, 40, 40)));
                }
            });
        });
    }

    fn tree_window(&mut self, ui: &mut Ui, sim: &Sim, out: &mut Vec<InputEvent>) {
        let title = if sim.menu().open { "Trees (menu open)" } else { "Trees" };
        egui::Window::new(title).id(egui::Id::unique("trees window")).default_pos([10.0, 60.0]).resizable(false).show(ui.ctx(), |ui| {
            // The shipped models and every bank's, by kind and then species (in catalogue
            // order within each), scrolling when the bank is long.
            egui::ScrollArea::vertical().max_height(420.0).show(ui, |ui| {
                for (kind, heading) in [(ModelKind::Mesh, "Mesh"), (ModelKind::Billboard, "Billboard")] {
                    let mut species: Vec<&str> = sim.catalogue().models.iter().filter(|m| m.kind == kind).map(|m| m.species.as_str()).collect();
                    species.sort_unstable();
                    species.dedup();
                    if species.is_empty() {
                        continue;
                    }
                    ui.label(RichText::new(heading).strong());
                    for sp in species {
                        ui.label(RichText::new(sp).small());
                        ui.horizontal_wrapped(|ui| {
                            for m in sim.catalogue().models.iter().filter(|m| m.kind == kind && m.species == sp) {
                                let current = sim.menu().current_model == m.id;
                                let thumb = self.thumbnails.get(usize::from(m.id.0)).copied().flatten();
                                let button = match thumb {
                                    Some(tex) => egui::Button::image_and_text(egui::Image::new((tex, egui::vec2(64.0, 64.0))), m.name.as_str()),
                                    None => egui::Button::new(m.name.as_str()),
                                };
                                if ui.add(button.selected(current)).clicked() {
                                    if sim.mode() == Mode::Manual && !sim.menu().open {
                                        out.push(InputEvent::OpenMenu);
                                    }
                                    out.push(InputEvent::ChooseModel { model: m.name.as_str().into() });
                                }
                            }
                        });
                    }
                }
            });
            if sim.menu().open && ui.button("Close menu").clicked() {
                out.push(InputEvent::CloseMenu);
            }
        });
    }

    fn quit_dialog(&mut self, ui: &mut Ui, sim: &Sim) {
        let modal = egui::Modal::new(egui::Id::unique("quit confirmation")).show(ui.ctx(), |ui| {
            ui.heading("Quit the session?");
            if sim.task().is_some_and(|t| !t.is_over()) {
                ui.label("The task is still running; quitting now leaves it unfinished.");
            }
            if let Some(path) = &self.stats.recording {
                ui.label(format!("The recording is completed and saved to {path}."));
            }
            ui.horizontal(|ui| {
                if ui.button("Quit").clicked() {
                    self.quit = true;
                }
                if ui.button("Keep going").clicked() {
                    self.confirm_quit = false;
                }
            });
            ui.label(RichText::new("Enter quits, Escape keeps going.").weak());
        });
        if modal.should_close() && !self.quit {
            self.confirm_quit = false;
        }
    }

    fn debug_window(&mut self, ui: &mut Ui, sim: &Sim) {
        egui::Window::new("Debug").default_pos([1000.0, 60.0]).resizable(false).show(ui.ctx(), |ui| {
            let c = sim.counts();
            ui.label(format!("{:.1} fps, frame {:.1} ms (mean over 1 s)", self.stats.fps, self.stats.frame_ms));
            ui.label(format!("sim {:.0} ticks/s (target {:.0})", self.stats.ticks_per_s, 1.0 / sim.dt().max(1e-6)));
            if let Some(((w, h), (fw, fh))) = self.stats.view_size {
                let shadows = if self.stats.shadows_off { ", shadows off" } else { "" };
                ui.label(format!("3D view {w}×{h} of {fw}×{fh} ({:.0} %{shadows})", 100.0 * w as f32 / fw.max(1) as f32));
            }
            ui.label(format!("tick {} ({:.2} s)", sim.tick(), sim.time()));
            ui.label(format!("entities {}: {} trees, {} planes", c.total, c.trees, c.planes));
            ui.label(format!("mode {}, model {}", sim.mode().name(), sim.catalogue().get(sim.menu().current_model).map_or("?", |m| m.name.as_str())));
            ui.label(format!("GPU {}", if self.stats.adapter.is_empty() { "none" } else { &self.stats.adapter }));
        });
    }
}

/// The result of a task whose clock has stopped: time, trees and errors, as `grove replay` and
/// `grove study` report them.
fn result_window(ui: &mut Ui, r: &TaskReport, sim: &Sim) {
    egui::Window::new("Task result").collapsible(false).resizable(false).anchor(egui::Align2::CENTER_TOP, [0.0, 60.0]).show(ui.ctx(), |ui| {
        let targets = sim.task().map_or(0, |t| t.def.targets.len());
        ui.heading(if r.completed { "All targets done" } else { "Task ended" });
        egui::Grid::new("task result").show(ui, |ui| {
            ui.label("time");
            ui.label(RichText::new(format!("{:.2} s", r.time_s)).monospace());
            ui.end_row();
            ui.label("trees");
            ui.label(RichText::new(format!("{} of {targets}", r.trees.len())).monospace());
            ui.end_row();
            ui.label("errors");
            ui.label(RichText::new(format!("{}", r.errors)).monospace());
            ui.end_row();
        });
    });
}

/// The task panel: targets with check marks and per-tree times, the running timer, and (when
/// `interactive`) the finish button.
pub fn task_panel(ui: &mut Ui, sim: &Sim, out: &mut Vec<InputEvent>, interactive: bool) {
    let Some(task) = sim.task() else { return };
    egui::Panel::right("task panel").resizable(false).show(ui, |ui| {
        ui.heading(format!("Task {}", task.def.id));
        let end = task.end_tick().unwrap_or(sim.tick());
        let secs = end.saturating_sub(task.started_tick) as f64 * sim.dt() as f64;
        ui.label(RichText::new(format!("time {secs:.1} s")).monospace().size(18.0));
        if task.is_complete() {
            ui.label(RichText::new("all targets done").color(Color32::from_rgb(40, 200, 90)));
        }
        ui.separator();
        for (i, t) in task.def.targets.iter().enumerate() {
            let hit = task.satisfied.get(i).copied().flatten();
            let mark = if hit.is_some() { "[x]" } else { "[ ]" };
            let time = hit.map(|h| format!(" {:.1} s", (h.tick - task.started_tick) as f64 * sim.dt() as f64)).unwrap_or_default();
            ui.label(format!("{mark} {} at ({:.1}, {:.1}){time}", t.model, t.position.x, t.position.z));
        }
        ui.separator();
        ui.label(format!("errors {}", task.errors.total()));
        if interactive && task.ended_tick.is_none() && ui.button("Finish task").clicked() {
            out.push(InputEvent::EndTask);
        }
    });
}


/// A technique's tooltip: its description, then each controller button it uses with the desktop
/// key or mouse button that produces it (`Technique::controls`).
fn technique_help(name: &str) -> String {
    let all = grove_systems::technique::installed();
    let Some(t) = all.get(name) else { return String::new() };
    let mut s = t.about.to_string();
    for c in &t.controls {
        s += &format!("\n{:?}: {} ({})", c.button, c.action, c.desktop);
    }
    s
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
        let birch = sim.catalogue().by_name("birch-billboard").unwrap().id;
        assert_eq!(sim.menu().current_model, birch);

        // Plant it with the controller: aim at the ground in front and click.
        let s = &mut h.state_mut().session;
        let pose = Pose::looking_at(Vec3::new(0.0, 1.7, 6.0), Vec3::new(1.0, 0.0, 1.0));
        s.queue(InputEvent::ControllerPose { pose }).unwrap();
        s.queue(InputEvent::ButtonDown { button: Button::Trigger }).unwrap();
        s.queue(InputEvent::ButtonUp { button: Button::Trigger }).unwrap();
        settle(&mut h);
        let sim = &h.state().session.sim;
        let mut planted = Vec::new();
        sim.for_each_tree(|v| planted.extend(Some(v.model).filter(|m| *m == birch)));
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
        assert_eq!(h.state().session.sim.mode(), Mode::Manual);
        let before = h.state().session.sim.counts().trees;
        h.get_by_label("conifer-mesh").click();
        settle(&mut h);
        let sim = &h.state().session.sim;
        assert_eq!(sim.counts().trees, before + 1, "manual mode: choosing from the menu spawns a tree");
        assert_eq!(sim.log().count("menu_opened"), 1);
    }

    #[test]
    fn starting_a_task_shows_its_targets_and_timer() {
        let mut h = harness();
        h.get_by_label("Task manual-7").click();
        settle(&mut h);
        {
            let sim = &h.state().session.sim;
            let task = sim.task().expect("the task started");
            assert_eq!(task.def.id, "manual-7");
            assert_eq!(sim.mode(), Mode::Manual);
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
        assert!(h.state().session.sim.task().unwrap().ended_tick.is_some());
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
