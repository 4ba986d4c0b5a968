//! Checks that the names a recording uses exist: the header's task, session start and block,
//! and the models and tasks its events name. The replay reader calls these, so a recording that
//! names something unknown is invalid input (exit 2) rather than a session that silently does
//! nothing.

use crate::input::InputEvent;
use super::Header;
use crate::sim::Sim;

/// Checks the header fields that name things: the task must be a known task, the optional
/// session start a valid RFC 3339 time, the optional block at least 1.
pub fn check_header(header: &Header) -> Result<(), String> {
    if let Some(task) = &header.task
        && crate::task::TaskDef::builtin(task).is_none()
    {
        let known: Vec<&str> = crate::task::BUILTIN_TASKS.iter().map(|(id, _)| *id).collect();
        return Err(format!("header names unknown task '{task}'; known tasks: {}", known.join(", ")));
    }
    if let Some(start) = &header.session_start
        && chrono::DateTime::parse_from_rfc3339(start).is_err()
    {
        return Err(format!("header session_start '{start}' is not an RFC 3339 time such as 2019-06-03T09:00:00Z"));
    }
    if header.block == Some(0) {
        return Err("header block must be 1 or more".into());
    }
    if let Some(t) = &header.technique {
        let registered = crate::technique::installed();
        match registered.get(&t.name) {
            None => return Err(format!("recording uses {}", registered.unknown(&t.name))),
            Some(k) if k.version != t.version => {
                return Err(format!("recording uses technique '{}' version {}, but version {} is registered", t.name, t.version, k.version));
            }
            Some(_) => {}
        }
    }
    for m in &header.models {
        if !crate::bank::valid_name(&m.name) || m.hash.len() != 16 || !m.hash.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(format!("header models: '{}' needs a plain name and a 16-hex-digit hash", m.name.escape_debug()));
        }
    }
    Ok(())
}

/// Checks that an event names only things that exist: a chosen model must be in the catalogue
/// and a started task must be a known task.
pub fn check_event(event: &InputEvent, sim: &Sim) -> Result<(), String> {
    match event {
        InputEvent::ChooseModel { model } => sim.res.catalogue.resolve(model).map(|_| ()).map_err(|e| format!("choose_model names an {e}")),
        InputEvent::StartTask { task } if crate::task::TaskDef::builtin(task).is_none() => Err(format!("start_task names unknown task '{task}'")),
        InputEvent::SwitchTechnique { technique } if sim.res.techniques.get(technique).is_none() => Err(format!("recording uses {}", sim.res.techniques.unknown(technique))),
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
            let e = check_header(&x).unwrap_err();
            assert!(e.contains(needle), "{e}");
        };
        bad(&|x| x.task = Some("manual-8".into()), "unknown task 'manual-8'");
        bad(&|x| x.session_start = Some("3 June 2019".into()), "RFC 3339");
        bad(&|x| x.block = Some(0), "block");
    }
}
