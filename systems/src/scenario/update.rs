//! Pinning world hashes in a scenario file's text (`grove test --update`), keeping everything
//! else (comments, layout, order) as the author wrote it.

/// The byte ranges of the string inside each `Hash("…")` of the text, in text order, outside
/// comments and other strings.
fn hash_literals(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < b.len() && !(b[i] == b'*' && b.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i += 2;
            }
            b'"' => i = skip_string(b, i),
            b'H' if text[i..].starts_with("Hash")
                && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) =>
            {
                let mut j = i + 4;
                while j < b.len() && b[j].is_ascii_whitespace() {
                    j += 1;
                }
                if b.get(j) != Some(&b'(') {
                    i += 4;
                    continue;
                }
                j += 1;
                while j < b.len() && b[j].is_ascii_whitespace() {
                    j += 1;
                }
                if b.get(j) == Some(&b'"') {
                    let end = skip_string(b, j);
                    out.push((j + 1, end.saturating_sub(1)));
                    i = end;
                } else {
                    i = j;
                }
            }
            _ => i += 1,
        }
    }
    out
}

/// The index just past the string literal that starts at `start` (a `"`).
fn skip_string(b: &[u8], start: usize) -> usize {
    let mut i = start + 1;
    while i < b.len() && b[i] != b'"' {
        i += if b[i] == b'\\' { 2 } else { 1 };
    }
    (i + 1).min(b.len())
}

/// Whether the top-level `expect:` list comes before `steps:` in the text (so its hashes come
/// first in text order).
fn expect_first(text: &str) -> bool {
    let find = |word: &str| {
        text.match_indices(word).find(|(k, _)| {
            let before = text[..*k].chars().last();
            let after = text[k + word.len()..].trim_start().starts_with(':');
            after && !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
    };
    matches!((find("expect"), find("steps")), (Some((e, _)), Some((s, _))) if e < s)
}

/// Rewrites the text's `Hash("…")` values with `hashes` (in run order: steps, then the end
/// expectations, `step_hashes` of them from the steps). Errors when the text does not hold
/// exactly as many hash literals as the run met.
pub fn pin_hashes(text: &str, hashes: &[String], step_hashes: usize) -> Result<String, super::HashCountError> {
    let spans = hash_literals(text);
    if spans.len() != hashes.len() {
        return Err(super::HashCountError { found: spans.len(), checked: hashes.len() });
    }
    let mut ordered: Vec<&String> = hashes.iter().collect();
    if expect_first(text) {
        ordered.rotate_left(step_hashes);
    }
    let mut out = String::with_capacity(text.len());
    let mut last = 0;
    for ((from, to), h) in spans.iter().zip(ordered) {
        out.push_str(&text[last..*from]);
        out.push_str(h);
        last = *to;
    }
    out.push_str(&text[last..]);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hashes_are_replaced_in_order_and_comments_kept() {
        let text = "// Hash(\"zz\") in a comment\n(steps: [Expect(Hash(\"\"))], expect: [Hash( \"0000000000000000\" ), TreeCount(1)])";
        let out = pin_hashes(text, &["aaaaaaaaaaaaaaaa".into(), "bbbbbbbbbbbbbbbb".into()], 1).unwrap();
        assert_eq!(
            out,
            "// Hash(\"zz\") in a comment\n(steps: [Expect(Hash(\"aaaaaaaaaaaaaaaa\"))], expect: [Hash( \"bbbbbbbbbbbbbbbb\" ), TreeCount(1)])"
        );
    }

    #[test]
    fn expect_before_steps_takes_the_end_hashes_first() {
        let text = "(expect: [Hash(\"\")], steps: [Expect(Hash(\"\"))])";
        let out = pin_hashes(text, &["1111111111111111".into(), "2222222222222222".into()], 1).unwrap();
        assert_eq!(out, "(expect: [Hash(\"2222222222222222\")], steps: [Expect(Hash(\"1111111111111111\"))])");
    }

    #[test]
    fn a_count_that_differs_is_refused() {
        assert!(pin_hashes("(steps: [], expect: [Hash(\"\")])", &[], 0).is_err());
    }
}
