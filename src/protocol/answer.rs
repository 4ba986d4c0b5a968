//! Whether an answer fits its item: a whole number in a rating's, scale's or Likert item's
//! range, a choice the item offers, text within its limit, yes or no. The answer is kept as
//! given (JSON); a refusal says why in one line.

use serde_json::Value;

use super::format::{Item, ItemKind};

/// An answer that does not fit its item: the reason, one line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{reason}")]
pub struct BadAnswer {
    /// Why, naming the item.
    pub reason: String,
}

/// Checks `answer` against `item`.
pub fn check(item: &Item, answer: &Value) -> Result<(), BadAnswer> {
    fits(item, answer).map_err(|reason| BadAnswer { reason })
}

/// Whether `answer` fits `item`; the error is the reason.
fn fits(item: &Item, answer: &Value) -> Result<(), String> {
    let id = &item.id;
    let whole = |lo: i64, hi: i64, step: i64| -> Result<(), String> {
        let v = answer.as_i64().ok_or_else(|| format!("item '{id}' takes a whole number from {lo} to {hi}, not {}", short(answer)))?;
        if v < lo || v > hi {
            return Err(format!("item '{id}' takes a whole number from {lo} to {hi}; {v} is out of range"));
        }
        if (v - lo) % step != 0 {
            return Err(format!("item '{id}' takes steps of {step} from {lo}; {v} is not one"));
        }
        Ok(())
    };
    match &item.kind {
        ItemKind::Rating { .. } => whole(0, 10, 1),
        ItemKind::Scale { min, max, step, .. } => whole(*min, *max, *step),
        ItemKind::Likert { points, .. } => whole(1, *points, 1),
        ItemKind::Single { choices } => {
            let s = answer.as_str().ok_or_else(|| format!("item '{id}' takes one of its choices (a string), not {}", short(answer)))?;
            if !choices.iter().any(|c| c == s) {
                return Err(format!("item '{id}' has no choice '{}' (its choices: {})", clip(s), choices.join(", ")));
            }
            Ok(())
        }
        ItemKind::Multiple { choices } => {
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
        ItemKind::Text { max_chars } => {
            let s = answer.as_str().ok_or_else(|| format!("item '{id}' takes text, not {}", short(answer)))?;
            let n = s.chars().count();
            if n > *max_chars {
                return Err(format!("item '{id}' takes at most {max_chars} characters; the answer has {n}"));
            }
            Ok(())
        }
        ItemKind::YesNo => answer.as_bool().map(|_| ()).ok_or_else(|| format!("item '{id}' takes yes or no (true or false), not {}", short(answer))),
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
