//! The shipped instruments, compiled in from `assets/protocols/`: the System Usability Scale and
//! raw NASA-TLX. A protocol names them by id without declaring them.

use super::format::Instrument;

/// The ids of the shipped instruments.
pub const IDS: &[&str] = &["sus", "nasa-tlx"];

const TEXTS: &[&str] =
    &[include_str!("../../assets/protocols/sus.ron"), include_str!("../../assets/protocols/nasa-tlx.ron")];

/// A shipped instrument by id.
pub fn get(id: &str) -> Option<Instrument> {
    let i = IDS.iter().position(|x| *x == id)?;
    ron::from_str(TEXTS[i]).ok()
}
