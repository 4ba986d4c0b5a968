//! Checks that the names a recording uses exist: the header's task, session start and block,
//! and the models and tasks its events name. The replay reader calls these, so a recording that
//! names something unknown is invalid input (exit 2) rather than a session that silently does
//! nothing.

use crate::catalogue::UnknownModel;
use crate::input::InputEvent;
use super::Header;
use crate::sim::Sim;

/// A name in a recording that does not exist, or a header field that is not well formed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NameError {
    /// The header's task is not a built-in task.
    #[error("header names unknown task '{task}'; known tasks: {}", known_tasks())]
    UnknownTask {
        /// The task as written.
        task: String,
    },
    /// The header's session start is not an RFC 3339 time.
    #[error("header session_start '{0}' is not an RFC 3339 time such as 2019-06-03T09:00:00Z")]
    SessionStart(String),
    /// The header's block is 0.
    #[error("header block must be 1 or more")]
    BlockZero,
    /// A technique that is not registered; the registry's sentence naming it and the known ones.
    #[error("recording uses {0}")]
    UnknownTechnique(String),
    /// The header's technique is registered with another version.
    #[error("recording uses technique '{name}' version {recorded}, but version {registered} is registered")]
    TechniqueVersion {
        /// The technique.
        name: String,
        /// The version the recording names.
        recorded: u32,
        /// The version this build registers.
        registered: u32,
    },
    /// A header model without a plain name or a 16-hex-digit hash.
    #[error("header models: '{}' needs a plain name and a 16-hex-digit hash", .0.escape_debug())]
    HeaderModel(String),
    /// A `choose_model` event names a model the catalogue does not have.
    #[error("choose_model names an {0}")]
    ChooseModel(UnknownModel),
    /// A header device field that is not 1 to 64 lowercase letters, digits and `-`.
    #[error("header device: {field} '{}' must be 1 to 64 lowercase letters, digits and '-'", .value.escape_debug())]
    Device {
        /// The field, e.g. "profile".
        field: &'static str,
        /// The value as written (at most 80 characters of it).
        value: String,
    },
    /// A `start_task` event names a task that is not built in.
    #[error("start_task names unknown task '{0}'")]
    StartTask(String),
}

/// The built-in tasks, comma-separated.
fn known_tasks() -> String {
    let known: Vec<&str> = crate::task::BUILTIN_TASKS.iter().map(|(id, _)| *id).collect();
    known.join(", ")
}

/// Checks the header fields that name things: the task must be a known task, the optional
/// session start a valid RFC 3339 time, the optional block at least 1.
pub fn check_header(header: &Header) -> Result<(), NameError> {
    if let Some(task) = &header.task
        && crate::task::TaskDef::builtin(task).is_none()
    {
        return Err(NameError::UnknownTask { task: task.clone() });
    }
    if let Some(start) = &header.session_start
        && chrono::DateTime::parse_from_rfc3339(start).is_err()
    {
        return Err(NameError::SessionStart(start.clone()));
    }
    if header.block == Some(0) {
        return Err(NameError::BlockZero);
    }
    if let Some(t) = &header.technique {
        let registered = crate::technique::installed();
        match registered.get(&t.name) {
            None => return Err(NameError::UnknownTechnique(registered.unknown(&t.name))),
            Some(k) if k.version != t.version => {
                return Err(NameError::TechniqueVersion { name: t.name.clone(), recorded: t.version, registered: k.version });
            }
            Some(_) => {}
        }
    }
    if let Some(d) = &header.device {
        for (field, value) in [("profile", &d.profile), ("target_ray_mode", &d.target_ray_mode), ("mapping", &d.mapping)] {
            if value.is_empty() || value.len() > 64 || !value.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-') {
                return Err(NameError::Device { field, value: value.chars().take(80).collect() });
            }
        }
    }
    for m in &header.models {
        if !crate::bank::valid_name(&m.name) || m.hash.len() != 16 || !m.hash.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(NameError::HeaderModel(m.name.clone()));
        }
    }
    Ok(())
}

/// Checks that an event names only things that exist: a chosen model must be in the catalogue
/// and a started task must be a known task.
pub fn check_event(event: &InputEvent, sim: &Sim) -> Result<(), NameError> {
    match event {
        InputEvent::ChooseModel { model } => sim.res.catalogue.resolve(model).map(|_| ()).map_err(NameError::ChooseModel),
        InputEvent::StartTask { task, .. } if crate::task::TaskDef::builtin(task).is_none() => Err(NameError::StartTask(task.clone())),
        InputEvent::SwitchTechnique { technique } if sim.res.techniques.get(technique).is_none() => Err(NameError::UnknownTechnique(sim.res.techniques.unknown(technique))),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_names_must_exist_and_optional_fields_must_be_well_formed() {
        let mut h = Header::new("study", 1, 1.0 / 60.0);
        assert!(check_header(&h).is_ok(), "no task, no session fields");
        h.task = Some("manual-7".into());
        h.session_start = Some("2019-06-03T09:00:00Z".into());
        h.block = Some(2);
        assert!(check_header(&h).is_ok());
        let bad = |f: &dyn Fn(&mut Header), needle: &str| {
            let mut x = h.clone();
            f(&mut x);
            let e = check_header(&x).unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
        };
        bad(&|x| x.task = Some("manual-8".into()), "unknown task 'manual-8'");
        bad(&|x| x.session_start = Some("3 June 2019".into()), "RFC 3339");
        bad(&|x| x.block = Some(0), "block");
        let device = |mapping: &str| super::super::HeaderDevice { profile: "generic-hand".into(), target_ray_mode: "tracked-pointer".into(), mapping: mapping.into() };
        let mut with_device = h.clone();
        with_device.device = Some(device("hands"));
        assert!(check_header(&with_device).is_ok());
        bad(&|x| x.device = Some(device("Hands!")), "header device: mapping 'Hands!'");
        bad(&|x| x.device = Some(device("")), "mapping ''");
    }
}
