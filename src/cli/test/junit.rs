//! JUnit XML for CI systems (`grove test --junit`): one `<testsuite>` of scenarios, one
//! `<testcase>` each, a `<failure>` with the reason where one failed. Written by hand, with every
//! attribute and text escaped and the characters XML 1.0 forbids dropped.

use std::fmt::Write;

/// One scenario's result.
pub struct Case {
    /// The scenario's name.
    pub name: String,
    /// Its file.
    pub file: String,
    /// Seconds it ran.
    pub seconds: f64,
    /// The failure line and the details under it, if it failed.
    pub failure: Option<(String, String)>,
}

/// Escapes text for an attribute value or element content.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {}
            c => out.push(c),
        }
    }
    out
}

/// The time as JUnit writes it: seconds with three decimals.
pub fn seconds(s: f64) -> String {
    format!("{:.3}", s)
}

/// The whole document. The suite's time is the sum of its cases' (rounded) times.
pub fn document(suite: &str, cases: &[Case]) -> String {
    let failures = cases.iter().filter(|c| c.failure.is_some()).count();
    let total: f64 = cases.iter().map(|c| seconds(c.seconds).parse::<f64>().unwrap_or(0.0)).sum();
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        x,
        "<testsuites name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"0\" time=\"{}\">",
        escape(suite),
        cases.len(),
        seconds(total)
    );
    let _ = writeln!(
        x,
        "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"0\" skipped=\"0\" time=\"{}\">",
        escape(suite),
        cases.len(),
        seconds(total)
    );
    for c in cases {
        let head = format!(
            "    <testcase name=\"{}\" classname=\"grove.scenarios\" file=\"{}\" time=\"{}\"",
            escape(&c.name),
            escape(&c.file),
            seconds(c.seconds)
        );
        match &c.failure {
            None => {
                let _ = writeln!(x, "{head}/>");
            }
            Some((message, details)) => {
                let _ = writeln!(x, "{head}>");
                let _ = writeln!(
                    x,
                    "      <failure message=\"{}\" type=\"expectation\">{}</failure>",
                    escape(message),
                    escape(details)
                );
                let _ = writeln!(x, "    </testcase>");
            }
        }
    }
    x.push_str("  </testsuite>\n</testsuites>\n");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markup_and_control_characters_are_escaped_or_dropped() {
        assert_eq!(escape("a<b & \"c\" 'd'>\u{1}e"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;e");
    }

    #[test]
    fn counts_and_times_add_up() {
        let cases = vec![
            Case { name: "a".into(), file: "a.ron".into(), seconds: 0.1234, failure: None },
            Case {
                name: "b<".into(),
                file: "b.ron".into(),
                seconds: 0.5,
                failure: Some(("step 1 x".into(), "more".into())),
            },
        ];
        let doc = document("grove", &cases);
        assert!(doc.contains("tests=\"2\" failures=\"1\" errors=\"0\" time=\"0.623\""), "{doc}");
        assert!(doc.contains("<testcase name=\"b&lt;\""), "{doc}");
        assert!(doc.contains("<failure message=\"step 1 x\" type=\"expectation\">more</failure>"), "{doc}");
    }
}
