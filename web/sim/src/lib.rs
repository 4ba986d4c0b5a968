//! grove-web-sim: grove's simulation (grove-systems, and the gaze-dwell plug-in technique) as a
//! WebAssembly module for JavaScript, bit for bit the native build's world.
//!
//! The module offers a small C ABI over UTF-8 JSON strings ([`abi`]; `web/sim/grove-sim.mjs`
//! is its JavaScript loader): make a simulation from a built-in scene or a scene's text, a seed
//! and `--set` overrides, or from a recording's header line ([`options`]); push input events as
//! a recording's event lines hold them, step one tick, read a typed snapshot, and record
//! ([`session`]); replay and verify a whole recording as `grove replay` does ([`replay`]); the
//! native renderer's wind displacement of tree vertices by its CPU reference ([`wind`]).
//! Every refusal is an [`Error`] value naming the problem; nothing traps, and a refused call
//! leaves the simulation as it was. See `web/sim/README.md` and `docs/wasm.md`.
//!
//! It knows no file system, clock, thread, GPU or window: scenes come as text, and the caller
//! measures time.

pub mod abi;
pub mod error;
pub mod options;
pub mod replay;
pub mod session;
pub mod wind;
#[cfg(test)]
mod tests;

pub use error::Error;
pub use session::Session;

/// Registers the techniques every simulation of the module knows (the built-in two and the
/// gaze-dwell plug-in, as the `grove` app registers them); once, on the first call that makes a
/// simulation.
pub fn install_techniques() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if let Ok(all) = grove_systems::technique::Techniques::with(vec![grove_gaze_dwell::technique()]) {
            // Refused only when already installed, which the `Once` rules out in this crate.
            let _ = grove_systems::technique::install(all);
        }
    });
}
