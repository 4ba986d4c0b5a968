//! Whether an answer fits its item: a whole number in a rating's, scale's or Likert item's
//! range, a choice the item offers, text within its limit, yes or no. What each kind of item
//! takes is stated once, by [`takes`]: the check here and the options the pages offer
//! (`form.rs`) both read it. The answer is kept as given (JSON); a refusal says why in one line.

use serde_json::Value;

use super::format::{Item, ItemKind};

/// The answers an item takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Takes<'a> {
    /// A whole number from `lo` to `hi` in steps of `step` from `lo`.
    Whole {
        /// The lowest.
        lo: i64,
        /// The highest.
        hi: i64,
        /// The step.
        step: i64,
    },
    /// One of the choices (a string).
    One(&'a [String]),
    /// A list of distinct choices, none included.
    Several(&'a [String]),
    /// Text of at most `max_chars` characters.
    Text {
        /// The longest answer in characters.
        max_chars: usize,
    },
    /// Yes or no (true or false).
    YesNo,
}

/// What an item of `kind` takes.
pub fn takes(kind: &ItemKind) -> Takes<'_> {
    match kind {
        ItemKind::Rating { .. } => Takes::Whole { lo: 0, hi: 10, step: 1 },
        ItemKind::Scale { min, max, step, .. } => Takes::Whole { lo: *min, hi: *max, step: *step },
        ItemKind::Likert { points, .. } => Takes::Whole { lo: 1, hi: *points, step: 1 },
        ItemKind::Single { choices } => Takes::One(choices),
        ItemKind::Multiple { choices } => Takes::Several(choices),
        ItemKind::Text { max_chars } => Takes::Text { max_chars: *max_chars },
        ItemKind::YesNo => Takes::YesNo,
    }
}

/// An answer that does not fit its item: the reason, one line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{reason}")]
pub struct BadAnswer {
    /// Why, naming the item.
    pub reason: String,
}

/// Checks `answer` against `item`; the error is the reason, one line.
pub fn check(item: &Item, answer: &Value) -> Result<(), BadAnswer> {
    fits(item, answer).map_err(|reason| BadAnswer { reason })
}

/// Whether `answer` fits `item`; the error is the reason.
fn fits(item: &Item, answer: &Value) -> Result<(), String> {
    let id = &item.id;
    match takes(&item.kind) {
        Takes::Whole { lo, hi, step } => {
            let v = answer.as_i64().ok_or_else(|| format!("item '{id}' takes a whole number from {lo} to {hi}, not {}", short(answer)))?;
            if v < lo || v > hi {
                return Err(format!("item '{id}' takes a whole number from {lo} to {hi}; {v} is out of range"));
            }
            if step <= 0 || (v - lo) % step != 0 {
                return Err(format!("item '{id}' takes steps of {step} from {lo}; {v} is not one"));
            }
            Ok(())
        }
        Takes::One(choices) => {
            let s = answer.as_str().ok_or_else(|| format!("item '{id}' takes one of its choices (a string), not {}", short(answer)))?;
            if !choices.iter().any(|c| c == s) {
                return Err(format!("item '{id}' has no choice '{}' (its choices: {})", clip(s), choices.join(", ")));
            }
            Ok(())
        }
        Takes::Several(choices) => {
            let list = answer.as_array().ok_or_else(|| format!("item '{id}' takes a list of its choices, not {}", short(answer)))?;
            for (i, v) in list.iter().enumerate() {
                let s = v.as_str().ok_or_else(|| format!("item '{id}': every answer in the list is one of its choices (a string), not {}", short(v)))?;
                if !choices.iter().any(|c| c == s) {
                    return Err(format!("item '{id}' has no choice '{}' (its choices: {})", clip(s), choices.join(", ")));
                }
                if list[..i].contains(v) {
                    return Err(format!("item '{id}': choice '{s}' is given twice"));
                }
            }
            Ok(())
        }
        Takes::Text { max_chars } => {
            let s = answer.as_str().ok_or_else(|| format!("item '{id}' takes text, not {}", short(answer)))?;
            let n = s.chars().count();
            if n > max_chars {
                return Err(format!("item '{id}' takes at most {max_chars} characters; the answer has {n}"));
            }
            Ok(())
        }
        Takes::YesNo => answer.as_bool().map(|_| ()).ok_or_else(|| format!("item '{id}' takes yes or no (true or false), not {}", short(answer))),
    }
}

fn clip(s: &str) -> String {
    let mut c: String = s.chars().take(40).collect();
    if s.chars().count() > 40 {
        c.push('…');
    }
    c.replace(['\n', '\r'], " ")
}

fn short(v: &Value) -> String {
    clip(&v.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn item(kind: ItemKind) -> Item {
        Item { id: "q".into(), text: "Q?".into(), kind, required: true }
    }

    #[test]
    fn numbers_must_be_whole_and_in_range_and_on_a_step() {
        let r = item(ItemKind::Rating { anchors: vec!["a".into(), "b".into()] });
        assert!(check(&r, &json!(0)).is_ok() && check(&r, &json!(10)).is_ok());
        assert!(check(&r, &json!(11)).unwrap_err().reason.contains("out of range"));
        assert!(check(&r, &json!(-1)).is_err());
        assert!(check(&r, &json!(2.5)).is_err());
        assert!(check(&r, &json!("7")).is_err());
        let s = item(ItemKind::Scale { min: 0, max: 100, step: 5, anchors: vec![] });
        assert!(check(&s, &json!(35)).is_ok());
        assert!(check(&s, &json!(33)).unwrap_err().reason.contains("steps of 5"));
        let l = item(ItemKind::Likert { points: 5, anchors: vec![] });
        assert!(check(&l, &json!(1)).is_ok() && check(&l, &json!(5)).is_ok());
        assert!(check(&l, &json!(0)).is_err() && check(&l, &json!(6)).is_err());
    }

    #[test]
    fn choices_text_and_yes_no() {
        let one = item(ItemKind::Single { choices: vec!["a".into(), "b".into()] });
        assert!(check(&one, &json!("a")).is_ok());
        assert!(check(&one, &json!("c")).unwrap_err().reason.contains("no choice 'c'"));
        let many = item(ItemKind::Multiple { choices: vec!["a".into(), "b".into()] });
        assert!(check(&many, &json!([])).is_ok() && check(&many, &json!(["b", "a"])).is_ok());
        assert!(check(&many, &json!(["a", "a"])).unwrap_err().reason.contains("twice"));
        assert!(check(&many, &json!(["z"])).is_err());
        assert!(check(&many, &json!("a")).is_err());
        let text = item(ItemKind::Text { max_chars: 3 });
        assert!(check(&text, &json!("abç")).is_ok());
        assert!(check(&text, &json!("abcd")).unwrap_err().reason.contains("at most 3"));
        let yn = item(ItemKind::YesNo);
        assert!(check(&yn, &json!(true)).is_ok() && check(&yn, &json!("yes")).is_err());
    }
}
