//! L-system trees: grammars (context-free, stochastic, parametric), parallel derivation on the
//! CPU (`derive`) and with a wgpu compute pass (`gpu`, the only file here that uses wgpu), a 3D
//! turtle with a parallel interpretation (`turtle`) and a memoised one for deterministic grammars
//! (`memo`), and glTF tree models (`mesh`).
//!
//! After Lipp, Wonka and Wimmer, "Parallel Generation of L-Systems" (2009). The grammar file
//! format and the command line are described in `docs/lsystem.md`.

pub mod derive;
pub mod error;
pub mod expr;
pub mod gpu;
pub mod grammar;
pub mod memo;
pub mod mesh;
pub mod presets;
pub mod turtle;

pub use derive::{LString, Limits, derive, derive_threads};
pub use error::LsystemError;
pub use grammar::Grammar;
pub use turtle::Segment;
