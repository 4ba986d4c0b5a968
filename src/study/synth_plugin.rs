//! Synthetic participants of plug-in techniques, driven by the technique's participant model
//! ([`grove_systems::technique::Operator`]).
//!
//! A technique whose model aims with the head (`Operator::AimHead`) and plants by dwelling
//! (`Operator::Dwell`) is played here: the gaze sweeps to the target along a minimum-jerk
//! path in a Fitts time, its endpoint scattered by the effective-width convention, corrected
//! until the hit point lies within the aiming margin, and then held still for the dwell. The
//! constants are those of ray pointing (`docs/participants.md`); head pointing has its own
//! published constants, which a calibrated model would use instead.

use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{HitTarget, Pose};
use grove_systems::input::{Button, InputEvent};

use super::error::SynthError;
use super::participant::{angle_between, angular_width, scatter_direction, sweep};
use super::synth::{AIM_MARGIN, MAX_CORRECTIONS, POSE_EVERY, Participant, stuck};

impl Participant {
    fn gaze(&self) -> (Vec3, Vec3) {
        let h = self.script.head().pose;
        (h.position, h.forward())
    }

    /// Sweeps the gaze from where it looks to `to` in `ticks` ticks, a head pose every
    /// [`POSE_EVERY`] ticks.
    fn sweep_gaze(&mut self, to: Vec3, ticks: u64) {
        let (eye, from) = self.gaze();
        for k in 1..=ticks {
            if k % POSE_EVERY == 0 || k == ticks {
                let d = sweep(from, to, k as f64 / ticks as f64);
                self.script.push(InputEvent::HeadPose { pose: Pose::looking_at(eye, eye + d) });
            }
            self.script.wait(1);
        }
    }

    /// Aims the gaze at `point` (angular width `width`) with Fitts timing and scatter, then
    /// corrects until `ok` holds or the corrections run out.
    fn aim_gaze(&mut self, point: Vec3, width: f64, ok: &dyn Fn(&Sim) -> bool) {
        let mut sigma = self.skill.endpoint_sigma(width);
        for _ in 0..=MAX_CORRECTIONS {
            let (eye, dir) = self.gaze();
            let target = (point - eye).normalize();
            let time = self.skill.aim_time(angle_between(dir, target), width);
            let end = scatter_direction(&mut self.rng, target, sigma);
            let n = self.ticks(time);
            self.sweep_gaze(end, n);
            if ok(self.sim()) {
                return;
            }
            sigma *= 0.6;
        }
    }

    /// Places one target by gaze and dwell: choose the model if needed, aim the gaze, hold it
    /// for the dwell; a tree that lands off target is looked at and removed with Bumper.
    pub(crate) fn gaze_target(
        &mut self,
        pos: Vec3,
        model: ModelId,
        tolerance: f32,
        dwell_s: f64,
    ) -> Result<(), SynthError> {
        self.think();
        if self.sim().menu().current_model != model {
            self.choose(model);
        }
        let goal = Vec2::new(pos.x, pos.z);
        let margin = tolerance * AIM_MARGIN;
        for _ in 0..8 {
            let point = Vec3::new(pos.x, self.ground_at(pos.x, pos.z), pos.z);
            let (eye, _) = self.gaze();
            let width = angular_width(2.0 * margin as f64, (point - eye).length() as f64);
            let before = self.last_planted().map(|p| p.0);
            self.aim_gaze(point, width, &move |sim: &Sim| {
                let h = sim.hit_marker();
                h.visible
                    && matches!(h.target, HitTarget::Plane(_))
                    && Vec2::new(h.position.x, h.position.z).distance(goal) < margin
            });
            // Hold still until the dwell plants (a few ticks beyond it at most).
            let wait = self.ticks(dwell_s) + 6;
            for _ in 0..wait {
                if self.last_planted().map(|p| p.0) != before {
                    break;
                }
                self.script.wait(1);
            }
            let Some((id, at)) = self.last_planted().filter(|p| Some(p.0) != before) else {
                self.think();
                continue;
            };
            if Vec2::new(at.x, at.z).distance(goal) <= tolerance {
                return Ok(());
            }
            // Off target: look at the tree and remove it.
            self.think();
            if let Some(c) = self.tree_center(id) {
                let (eye, _) = self.gaze();
                let width = angular_width(1.0, (c - eye).length() as f64);
                self.aim_gaze(c, width, &move |sim: &Sim| {
                    let h = sim.hit_marker();
                    h.visible && h.target == HitTarget::Tree(id)
                });
                self.press(Button::Bumper);
            }
        }
        Err(stuck(&format!("could not plant at ({:.2}, {:.2}) by gaze after several tries", pos.x, pos.z)))
    }
}
