//! The grove application library: the asset generator and the wgpu renderer, shared by the
//! `grove` command-line tool, the desktop window and the tests.
//!
//! The simulation itself lives in the headless `grove-systems` crate; this crate only reads it.

#![warn(missing_docs)]

pub mod aerial;
pub mod assetgen;
pub mod atomic_write;
pub mod bank;
pub mod bench;
pub mod csv_cells;
pub mod cubemap;
pub mod error;
pub mod html;
pub mod render;
pub mod serve;
pub mod species;
pub mod lsystem;
pub mod models;
pub mod protocol;
pub mod study;
pub mod video;

pub use error::Error;
