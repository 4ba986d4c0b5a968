//! Every CSV file grove writes goes through this module's [`Writer`], and every cell through
//! [`cell`]: a text cell that begins with `=`, `+`, `-`, `@`, a tab or a carriage return is
//! written with a `'` before it, so that a spreadsheet shows it as text instead of running it as
//! a formula (OWASP's rule against CSV injection: a participant's free-text answer
//! `=HYPERLINK(…)` stays text). A cell that is a plain number (`-1.5`, `+3`, `2.5e-4`) is left
//! as it is: a spreadsheet reads it as a number, not a formula. `docs/reports.md` states the
//! rule for the reports' readers.

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use serde::Serialize;

/// The characters a spreadsheet may take as the start of a formula.
const FORMULA_START: [char; 6] = ['=', '+', '-', '@', '\t', '\r'];

/// Whether a text is a plain decimal number: an optional sign, digits with at most one point,
/// and an optional exponent. Nothing else a spreadsheet could run.
fn is_number(text: &str) -> bool {
    let unsigned = text.strip_prefix(['+', '-']).unwrap_or(text);
    let (mantissa, exponent) = match unsigned.find(['e', 'E']) {
        Some(i) => (&unsigned[..i], Some(&unsigned[i + 1..])),
        None => (unsigned, None),
    };
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let mantissa_ok = match mantissa.split_once('.') {
        Some((whole, frac)) => (digits(whole) || whole.is_empty()) && (digits(frac) || frac.is_empty()) && !(whole.is_empty() && frac.is_empty()),
        None => digits(mantissa),
    };
    let exponent_ok = exponent.is_none_or(|e| digits(e.strip_prefix(['+', '-']).unwrap_or(e)));
    mantissa_ok && exponent_ok
}

/// A cell as grove writes it: a text that a spreadsheet could take as a formula gets a `'`
/// before it; anything else, numbers included, is written as it is.
pub fn cell(text: &str) -> Cow<'_, str> {
    if text.starts_with(FORMULA_START) && !is_number(text) {
        Cow::Owned(format!("'{text}"))
    } else {
        Cow::Borrowed(text)
    }
}

/// A CSV writer whose every cell goes through [`cell`] (quoting as RFC 4180 needs, by the `csv`
/// crate).
pub struct Writer<W: Write> {
    inner: csv::Writer<W>,
    /// Whether [`Writer::serialize`] has written the header row of its rows' fields.
    headed: bool,
}

impl Writer<std::fs::File> {
    /// A writer of a new file at `path`.
    pub fn from_path(path: &Path) -> csv::Result<Writer<std::fs::File>> {
        Ok(Writer { inner: csv::Writer::from_path(path)?, headed: false })
    }
}

impl<W: Write> Writer<W> {
    /// A writer into `w`.
    pub fn from_writer(w: W) -> Writer<W> {
        Writer { inner: csv::Writer::from_writer(w), headed: false }
    }

    /// Writes one row.
    pub fn write_record<I, T>(&mut self, record: I) -> csv::Result<()>
    where
        I: IntoIterator<Item = T>,
        T: AsRef<str>,
    {
        let cells: Vec<String> = record.into_iter().map(|t| cell(t.as_ref()).into_owned()).collect();
        self.inner.write_record(&cells)
    }

    /// Writes a row of a struct's fields (before the first, a header row of their names), as
    /// `csv::Writer::serialize` does, every cell through [`cell`].
    pub fn serialize<S: Serialize>(&mut self, row: &S) -> csv::Result<()> {
        let mut scratch = csv::WriterBuilder::new().has_headers(!self.headed).from_writer(Vec::new());
        scratch.serialize(row)?;
        let bytes = scratch.into_inner().map_err(|e| csv::Error::from(e.into_error()))?;
        for record in csv::ReaderBuilder::new().has_headers(false).from_reader(bytes.as_slice()).records() {
            self.write_record(record?.iter())?;
        }
        self.headed = true;
        Ok(())
    }

    /// Hands what is buffered to the underlying writer.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_text_that_could_be_a_formula_is_written_as_text_and_a_number_stays_a_number() {
        for (text, written) in [
            ("=HYPERLINK(\"x\")", "'=HYPERLINK(\"x\")"),
            ("+1+1", "'+1+1"),
            ("-1+2", "'-1+2"),
            ("@SUM(A1)", "'@SUM(A1)"),
            ("\tx", "'\tx"),
            ("\r=1", "'\r=1"),
            ("-", "'-"),
            ("-inf", "'-inf"),
            ("-1.5", "-1.5"),
            ("+3", "+3"),
            ("-2.5e-4", "-2.5e-4"),
            ("-.5", "-.5"),
            ("1,5", "1,5"),
            ("teaching, with = inside", "teaching, with = inside"),
            ("P01", "P01"),
            ("", ""),
        ] {
            assert_eq!(cell(text), written, "{text:?}");
        }
    }

    #[test]
    fn every_cell_of_a_row_and_of_a_serialized_struct_goes_through_the_rule() {
        #[derive(Serialize)]
        struct Row {
            species: String,
            x_m: f64,
        }
        let text = |w: Writer<Vec<u8>>| String::from_utf8(w.inner.into_inner().map_err(|e| e.into_error()).unwrap()).unwrap();
        let mut w = Writer::from_writer(Vec::new());
        w.write_record(["P01", "=HYPERLINK(\"x\")", "-1.5"]).unwrap();
        w.flush().unwrap();
        assert_eq!(text(w), "P01,\"'=HYPERLINK(\"\"x\"\")\",-1.5\n");
        let mut w = Writer::from_writer(Vec::new());
        w.serialize(&Row { species: "@oak".into(), x_m: -2.25 }).unwrap();
        w.serialize(&Row { species: "birch".into(), x_m: 3.0 }).unwrap();
        w.flush().unwrap();
        assert_eq!(text(w), "species,x_m\n'@oak,-2.25\nbirch,3.0\n");
    }
}
