//! Ghosts: the other recordings of the same task in a folder, replayed beside the chosen one and
//! aligned at the task's start, each drawn as a figure (head and ray) in its participant's
//! colour; the chosen participant is drawn solid, the others as wire figures.

use std::path::{Path, PathBuf};

use crate::render::overlay::geometry::OverlayGhost;
use grove_systems::Sim;
use grove_systems::bank::Banks;
use grove_systems::replay::Player;

/// At most this many ghosts are drawn.
pub const MAX_GHOSTS: usize = 64;

/// How far a ray that hits nothing is drawn, metres.
const FREE_RAY_M: f32 = 3.0;

/// The colour of a participant: stable for an id whatever else is drawn. Ids ending in a
/// number (P01, P12, …) take that number's place on a wheel of twelve hues that puts
/// neighbours far apart (five steps of 30° each); other ids take a hash's place.
pub fn participant_color(id: &str) -> [f32; 4] {
    let digits: String =
        id.chars().rev().take_while(|c| c.is_ascii_digit()).collect::<Vec<_>>().into_iter().rev().collect();
    let n = match digits.parse::<u64>() {
        Ok(n) => n.wrapping_sub(1),
        Err(_) => xxhash_rust::xxh3::xxh3_64(id.as_bytes()),
    };
    let hue = ((n % 12) * 5 % 12) as f32 * 30.0;
    let [r, g, b] = hsv(hue, 0.8, 1.0);
    // sRGB to linear: the overlay's colours are linear.
    let lin = |c: f32| c.powf(2.2);
    [lin(r), lin(g), lin(b), 1.0]
}

fn hsv(h: f32, s: f32, v: f32) -> [f32; 3] {
    let c = v * s;
    let hp = (h / 60.0) % 6.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r + m, g + m, b + m]
}

/// A participant in `sim` as a figure: the head, and the controller's ray to its hit (or a
/// short free ray).
pub fn figure(sim: &Sim, color: [f32; 4], solid: bool) -> OverlayGhost {
    let head = sim.head();
    let ray = sim.controller().map_or((head.pose.position, head.pose.forward()), |c| (c.ray_origin(), c.ray_dir()));
    let ray_length = Some(sim.hit_marker()).filter(|h| h.visible).map_or(FREE_RAY_M, |h| h.distance);
    OverlayGhost { head: head.pose.position, head_rotation: head.pose.rotation, ray, ray_length, color, solid }
}

/// One other recording, replayed in step with the chosen one.
pub struct Ghost {
    /// Its participant id (the file name when the header has none).
    pub participant: String,
    /// Its colour.
    pub color: [f32; 4],
    player: Player,
    /// Its tick minus the chosen recording's, at the same moment of the task.
    offset: i64,
}

impl Ghost {
    /// Its figure when the chosen recording is at `tick`: its own world at the same time since
    /// the task's start (held at its first or last tick outside its recording).
    pub fn figure_at(&mut self, tick: u64) -> OverlayGhost {
        let last = self.player.final_tick().min(i64::MAX as u64) as i64;
        let t = (tick as i64).saturating_add(self.offset).clamp(0, last) as u64;
        self.player.advance_to(t);
        figure(self.player.sim(), self.color, false)
    }
}

/// Why the ghosts could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum GhostError {
    /// The folder cannot be listed.
    #[error("{0}: cannot list the folder ({1})")]
    Folder(String, String),
    /// A recording in it cannot be replayed.
    #[error("{0}")]
    Recording(String),
    /// More recordings of the task than can be drawn.
    #[error("{0}: {1} recordings of the task; at most {MAX_GHOSTS} can be drawn as ghosts")]
    TooMany(String, usize),
}

/// The recordings of `task` in `dir` other than `chosen`, opened and aligned: a ghost's tick is
/// the chosen tick plus its task start minus `chosen_start` (both the ticks of their
/// `start_task` events; recordings without one are aligned at tick 0).
pub fn open(
    dir: &Path,
    chosen: &Path,
    task: Option<&str>,
    chosen_start: Option<u64>,
    banks: &Banks,
) -> Result<Vec<Ghost>, GhostError> {
    let listing = std::fs::read_dir(dir).map_err(|e| GhostError::Folder(dir.display().to_string(), e.to_string()))?;
    let mut files: Vec<PathBuf> = listing
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "jsonl"))
        .collect();
    files.sort();
    let chosen = std::fs::canonicalize(chosen).ok();
    let mut ghosts = Vec::new();
    for f in files {
        if std::fs::canonicalize(&f).ok() == chosen {
            continue;
        }
        let player = Player::open(&f, &[], banks).map_err(|e| GhostError::Recording(e.to_string()))?;
        if player.header.task.as_deref() != task {
            continue;
        }
        let participant = player
            .header
            .participant
            .clone()
            .unwrap_or_else(|| f.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default());
        let offset = player.task_start_tick().unwrap_or(0) as i64 - chosen_start.unwrap_or(0) as i64;
        ghosts.push(Ghost { color: participant_color(&participant), participant, player, offset });
        if ghosts.len() > MAX_GHOSTS {
            return Err(GhostError::TooMany(dir.display().to_string(), ghosts.len()));
        }
    }
    Ok(ghosts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_participant_keeps_its_colour_and_the_study_participants_differ() {
        assert_eq!(participant_color("P03"), participant_color("P03"));
        let colours: Vec<[f32; 4]> = (1..=12).map(|i| participant_color(&format!("P{i:02}"))).collect();
        for i in 0..12 {
            for j in i + 1..12 {
                let d: f32 = (0..3).map(|k| (colours[i][k] - colours[j][k]).abs()).sum();
                assert!(d > 0.05, "P{:02} and P{:02} look alike: {:?} {:?}", i + 1, j + 1, colours[i], colours[j]);
            }
        }
        // Neighbours are far apart on the wheel: P01 red (0°), P02 150° (green-cyan).
        let [r, g, _, _] = participant_color("P01");
        assert!(r > 0.9 && g < 0.05);
        let [r, g, _, _] = participant_color("P02");
        assert!(g > 0.9 && r < 0.05);
        // Ids without a number still get a colour from the wheel.
        assert_eq!(participant_color("alice")[3], 1.0);
    }

    #[test]
    fn hsv_primaries() {
        assert_eq!(hsv(0.0, 1.0, 1.0), [1.0, 0.0, 0.0]);
        assert_eq!(hsv(120.0, 1.0, 1.0), [0.0, 1.0, 0.0]);
        assert_eq!(hsv(240.0, 1.0, 1.0), [0.0, 0.0, 1.0]);
    }
}
