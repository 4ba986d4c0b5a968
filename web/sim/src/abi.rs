//! The C ABI that JavaScript calls (`web/sim/grove-sim.mjs` is its loader).
//!
//! Strings go in as (pointer, length) pairs of UTF-8 bytes in the module's memory, written by
//! the caller into buffers from [`grove_alloc`] and given back with [`grove_free`]. Every call
//! leaves its answer in one result buffer ([`grove_result_ptr`], [`grove_result_len`]), valid
//! until the next call: a status below 0 means the result is an error's one-line message;
//! otherwise it is the call's answer (JSON, or recording lines each ending in a newline).
//! Simulations are named by handles (small integers) from [`grove_sim_new`].

use std::cell::RefCell;

use crate::error::Error;
use crate::replay::{replay, ReplayArgs};
use crate::session::Session;

#[derive(Default)]
struct State {
    sims: Vec<Option<Session>>,
    result: Vec<u8>,
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

/// Sets the result buffer and returns `status`, or -1 with the error's message.
fn answer(outcome: Result<(i32, Vec<u8>), Error>) -> i32 {
    let (status, bytes) = match outcome {
        Ok(ok) => ok,
        Err(e) => (-1, e.to_string().into_bytes()),
    };
    STATE.with(|s| s.borrow_mut().result = bytes);
    status
}

/// The caller's bytes as text.
///
/// # Safety
/// `ptr` must point to `len` readable bytes (or `len` be 0).
unsafe fn text<'a>(what: &'static str, ptr: *const u8, len: usize) -> Result<&'a str, Error> {
    let bytes: &[u8] = if len == 0 || ptr.is_null() { &[] } else { unsafe { std::slice::from_raw_parts(ptr, len) } };
    std::str::from_utf8(bytes).map_err(|e| Error::input(what, e))
}

fn lines(lines: Vec<String>) -> Vec<u8> {
    let mut out = Vec::with_capacity(lines.iter().map(|l| l.len() + 1).sum());
    for l in lines {
        out.extend_from_slice(l.as_bytes());
        out.push(b'\n');
    }
    out
}

fn json<T: serde::Serialize>(value: &T) -> Result<Vec<u8>, Error> {
    serde_json::to_vec(value).map_err(|e| Error::input("result", e))
}

/// Runs `f` on the simulation `handle`.
fn with_sim<T>(handle: u32, f: impl FnOnce(&mut Session) -> Result<T, Error>) -> Result<T, Error> {
    STATE.with(|s| {
        let mut s = s.borrow_mut();
        let sim = s.sims.get_mut(handle as usize).and_then(Option::as_mut).ok_or(Error::Handle(handle))?;
        f(sim)
    })
}

/// A buffer of `len` bytes for the caller to write into; give it back with [`grove_free`].
#[unsafe(no_mangle)]
pub extern "C" fn grove_alloc(len: usize) -> *mut u8 {
    let mut v = Vec::<u8>::with_capacity(len.max(1));
    let ptr = v.as_mut_ptr();
    std::mem::forget(v);
    ptr
}

/// Gives back a buffer from [`grove_alloc`].
///
/// # Safety
/// `ptr` and `len` must be exactly a pointer [`grove_alloc`] returned and the length it was
/// asked for, given back once.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_free(ptr: *mut u8, len: usize) {
    if !ptr.is_null() {
        drop(unsafe { Vec::from_raw_parts(ptr, 0, len.max(1)) });
    }
}

/// Where the last call's result starts.
#[unsafe(no_mangle)]
pub extern "C" fn grove_result_ptr() -> *const u8 {
    STATE.with(|s| s.borrow().result.as_ptr())
}

/// The last call's result's length in bytes.
#[unsafe(no_mangle)]
pub extern "C" fn grove_result_len() -> usize {
    STATE.with(|s| s.borrow().result.len())
}

/// Makes a simulation from its options (JSON, [`crate::options::Options`]): returns its handle
/// (the result: the lines made so far, a self-made recording's header line) or -1.
///
/// # Safety
/// `ptr` must point to `len` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_sim_new(ptr: *const u8, len: usize) -> i32 {
    let made = unsafe { text("options", ptr, len) }.and_then(Session::new);
    answer(made.map(|(session, made)| {
        let handle = STATE.with(|s| {
            let mut s = s.borrow_mut();
            match s.sims.iter().position(Option::is_none) {
                Some(i) => {
                    s.sims[i] = Some(session);
                    i
                }
                None => {
                    s.sims.push(Some(session));
                    s.sims.len() - 1
                }
            }
        });
        (handle as i32, lines(made))
    }))
}

/// Drops a simulation: 0, or -1 for an unknown handle.
#[unsafe(no_mangle)]
pub extern "C" fn grove_sim_free(handle: u32) -> i32 {
    let dropped = STATE.with(|s| s.borrow_mut().sims.get_mut(handle as usize).and_then(Option::take));
    answer(dropped.map(|_| (0, Vec::new())).ok_or(Error::Handle(handle)))
}

/// Queues an input event (JSON, see [`Session::push`]): 0 or -1.
///
/// # Safety
/// `ptr` must point to `len` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_sim_push(handle: u32, ptr: *const u8, len: usize) -> i32 {
    let pushed = unsafe { text("event", ptr, len) }.and_then(|t| with_sim(handle, |s| s.push(t)));
    answer(pushed.map(|()| (0, Vec::new())))
}

/// Runs one tick: 0 (the result: the recording lines it made) or -1.
#[unsafe(no_mangle)]
pub extern "C" fn grove_sim_step(handle: u32) -> i32 {
    answer(with_sim(handle, Session::step).map(|l| (0, lines(l))))
}

/// The world's snapshot as JSON ([`grove_systems::snapshot::Snapshot`]): 0 or -1.
#[unsafe(no_mangle)]
pub extern "C" fn grove_sim_snapshot(handle: u32) -> i32 {
    answer(with_sim(handle, |s| json(&s.snapshot())).map(|j| (0, j)))
}

/// The ground planes as JSON ([`Session::ground`]): 0 or -1.
#[unsafe(no_mangle)]
pub extern "C" fn grove_sim_ground(handle: u32) -> i32 {
    answer(with_sim(handle, |s| json(&s.ground())).map(|j| (0, j)))
}

/// The world hash (16 hex digits): 0 or -1.
#[unsafe(no_mangle)]
pub extern "C" fn grove_sim_hash(handle: u32) -> i32 {
    answer(with_sim(handle, |s| Ok(s.hash().into_bytes())).map(|h| (0, h)))
}

/// The simulation's tick (completed steps) as a number, or -1 for an unknown handle.
#[unsafe(no_mangle)]
pub extern "C" fn grove_sim_tick(handle: u32) -> f64 {
    with_sim(handle, |s| Ok(s.tick() as f64)).unwrap_or(-1.0)
}

/// Ends the recording (see [`Session::finish`]): 0 (the result: the lines made, the footer
/// last) or -1.
#[unsafe(no_mangle)]
pub extern "C" fn grove_sim_finish(handle: u32) -> i32 {
    answer(with_sim(handle, Session::finish).map(|l| (0, lines(l))))
}

/// Replays a recording and verifies it as `grove replay` does: `args` is JSON
/// ([`ReplayArgs`]), `recording` the file's bytes. 0 (the result: JSON
/// [`crate::replay::Replayed`]) or -1 (the result: the error line `grove replay` prints).
///
/// # Safety
/// Each pointer must point to its length of readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_replay(args_ptr: *const u8, args_len: usize, rec_ptr: *const u8, rec_len: usize) -> i32 {
    let run = || -> Result<Vec<u8>, Error> {
        let args: ReplayArgs = serde_json::from_str(unsafe { text("replay options", args_ptr, args_len) }?).map_err(|e| Error::input("replay options", e))?;
        let recording: &[u8] = if rec_len == 0 || rec_ptr.is_null() { &[] } else { unsafe { std::slice::from_raw_parts(rec_ptr, rec_len) } };
        json(&replay(&args, recording)?)
    };
    answer(run().map(|j| (0, j)))
}

/// Signs recording lines again as one chain (version 2; the header's checksum with seed 0), as
/// `grove replay --upgrade` does: a tool for tests and converters that edit a recording's lines.
/// `lines` is the text, one line each; 0 (the result: the lines re-signed) or -1.
///
/// # Safety
/// `ptr` must point to `len` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_rechain(ptr: *const u8, len: usize) -> i32 {
    let run = || -> Result<Vec<u8>, Error> {
        let text = unsafe { text("lines", ptr, len) }?;
        let input: Vec<String> = text.lines().map(str::to_string).collect();
        let signed = grove_systems::replay::rechain(&input).map_err(|e| Error::input("lines", e))?;
        Ok(lines(signed))
    };
    answer(run().map(|l| (0, l)))
}

/// Builds the scene of a room a headset found in AR: `input` is JSON (grove-systems'
/// `room::RoomInput`: `source`, `floor_y`, `planes` as `{ label, points: [{ x, y, z }, …] }` in the
/// simulation's frame, `task`). 0 (the result: the scene file's text, which `grove serve` takes
/// as `scene_text`) or -1.
///
/// # Safety
/// `ptr` must point to `len` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_room_scene(ptr: *const u8, len: usize) -> i32 {
    let run = || -> Result<Vec<u8>, Error> {
        let input: grove_systems::room::RoomInput = serde_json::from_str(unsafe { text("room", ptr, len) }?).map_err(|e| Error::input("room", e))?;
        Ok(grove_systems::room::room_scene(&input)?.into_bytes())
    };
    answer(run().map(|t| (0, t)))
}

/// A built-in task as JSON: `id`, `mode` ("ray-casting" or "manual", the mode it is done in),
/// `scene`, `tolerance`, `targets` (`position`, `model`). 0 or -1 for an unknown task.
///
/// # Safety
/// `ptr` must point to `len` readable bytes (the task's id).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_task(ptr: *const u8, len: usize) -> i32 {
    let run = || -> Result<Vec<u8>, Error> {
        let id = unsafe { text("task", ptr, len) }?;
        let def = grove_systems::task::TaskDef::builtin(id).ok_or_else(|| Error::input("task", format!("'{}' is not a built-in task", id.chars().take(64).collect::<String>())))?;
        json(&serde_json::json!({ "id": def.id, "mode": def.mode.name(), "scene": def.scene, "tolerance": def.tolerance, "targets": def.targets }))
    };
    answer(run().map(|j| (0, j)))
}

/// The native renderer's wind displacement of a tree's vertices ([`crate::wind`]): `ptr` is
/// JSON ([`crate::wind::WindIn`]); 0 (the result: JSON, each vertex's world position) or -1.
///
/// # Safety
/// `ptr` must point to `len` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn grove_wind_displace(ptr: *const u8, len: usize) -> i32 {
    let run = || -> Result<Vec<u8>, Error> { json(&crate::wind::displace_points(unsafe { text("wind", ptr, len) }?)?) };
    answer(run().map(|j| (0, j)))
}
