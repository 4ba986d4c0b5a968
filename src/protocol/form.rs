//! A questionnaire as the pages show it (the participant's form page `/protocol` and the
//! headset's panel, `docs/protocol.md`): each item with what it takes worked out here, from the
//! same statement the answers are checked against ([`super::answer::takes`]): its options in
//! order with their labels (a Likert item with a word for every point shows the words), the
//! anchors at the two ends, whether it takes several choices, and free text with its limit. The
//! pages lay these out and collect the participant's input; the server alone decides whether an
//! answer fits ([`super::answer::check`]).

use serde::Serialize;
use serde_json::Value;

use super::answer::{takes, Takes};
use super::format::{Instrument, Item, ItemKind, Scoring};

/// An instrument as the pages get it: the protocol's fields, its items as [`FormItem`]s.
#[derive(Clone, Debug, Serialize)]
pub struct FormInstrument {
    /// Its id.
    pub id: String,
    /// Its title.
    pub title: String,
    /// The sentence before the items.
    pub intro: String,
    /// How it is scored.
    pub scoring: Scoring,
    /// The items, in order.
    pub items: Vec<FormItem>,
}

/// One item as the pages get it: the protocol's item (`id`, `text`, `kind`, `required`) and what
/// it takes.
#[derive(Clone, Debug, Serialize)]
pub struct FormItem {
    /// The item as the protocol states it.
    #[serde(flatten)]
    pub item: Item,
    /// The answers to choose from, in order (none for free text).
    pub options: Vec<FormOption>,
    /// The words at the two ends of a row of numbers, if it has them.
    pub anchors: Option<[String; 2]>,
    /// Whether any number of the options is the answer (a list), rather than one.
    pub multi: bool,
    /// Whether the answer is typed text.
    pub typed: bool,
    /// The longest typed answer, in characters.
    pub max_chars: Option<usize>,
}

/// An answer to choose: the value sent, the words shown.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FormOption {
    /// The answer as sent (a number, a choice's text, true or false).
    pub value: Value,
    /// What its button or box says.
    pub label: String,
}

impl FormInstrument {
    /// The pages' form of `instrument`.
    pub fn new(instrument: &Instrument) -> FormInstrument {
        FormInstrument {
            id: instrument.id.clone(),
            title: instrument.title.clone(),
            intro: instrument.intro.clone(),
            scoring: instrument.scoring,
            items: instrument.items.iter().map(FormItem::new).collect(),
        }
    }
}

/// The first and last of `anchors`, if there are any.
fn ends(anchors: &[String]) -> Option<[String; 2]> {
    Some([anchors.first()?.clone(), anchors.last()?.clone()])
}

impl FormItem {
    /// The pages' form of `item`.
    pub fn new(item: &Item) -> FormItem {
        let mut form = FormItem { item: item.clone(), options: Vec::new(), anchors: None, multi: false, typed: false, max_chars: None };
        let words = |choices: &[String]| choices.iter().map(|c| FormOption { value: Value::from(c.as_str()), label: c.clone() }).collect();
        match takes(&item.kind) {
            Takes::Whole { lo, hi, step } => {
                let steps = if step > 0 && hi >= lo { (hi - lo) / step + 1 } else { 0 };
                form.options = (0..steps).map(|k| lo + k * step).map(|v| FormOption { value: Value::from(v), label: v.to_string() }).collect();
                let anchors = match &item.kind {
                    ItemKind::Rating { anchors } | ItemKind::Scale { anchors, .. } | ItemKind::Likert { anchors, .. } => anchors.as_slice(),
                    _ => &[],
                };
                // A word for every point (more than two): each option says its word, no anchors.
                if matches!(item.kind, ItemKind::Likert { .. }) && anchors.len() == form.options.len() && anchors.len() > 2 {
                    for (o, word) in form.options.iter_mut().zip(anchors) {
                        o.label = word.clone();
                    }
                } else {
                    form.anchors = ends(anchors);
                }
            }
            Takes::One(choices) => form.options = words(choices),
            Takes::Several(choices) => {
                form.options = words(choices);
                form.multi = true;
            }
            Takes::Text { max_chars } => {
                form.typed = true;
                form.max_chars = Some(max_chars);
            }
            Takes::YesNo => form.options = vec![FormOption { value: Value::Bool(true), label: "Yes".into() }, FormOption { value: Value::Bool(false), label: "No".into() }],
        }
        form
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn item(kind: ItemKind) -> FormItem {
        FormItem::new(&Item { id: "q".into(), text: "Q?".into(), kind, required: true })
    }

    fn words(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    fn pairs(f: &FormItem) -> Vec<(Value, String)> {
        f.options.iter().map(|o| (o.value.clone(), o.label.clone())).collect()
    }

    #[test]
    fn numbers_are_rows_of_options_with_the_anchors_at_their_ends() {
        let rating = item(ItemKind::Rating { anchors: words(&["Not at all", "Very well"]) });
        assert_eq!(rating.options.iter().map(|o| o.value.as_i64().unwrap()).collect::<Vec<_>>(), (0..=10).collect::<Vec<_>>());
        assert_eq!(rating.anchors, Some(["Not at all".to_string(), "Very well".to_string()]));
        let tlx = item(ItemKind::Scale { min: 0, max: 100, step: 5, anchors: words(&["Very low", "Very high"]) });
        assert_eq!(tlx.options.len(), 21);
        assert_eq!((tlx.options[20].value.clone(), tlx.options[20].label.as_str()), (Value::from(100), "100"));
        let sus = item(ItemKind::Likert { points: 5, anchors: words(&["Strongly disagree", "Strongly agree"]) });
        assert_eq!(sus.options.iter().map(|o| o.label.as_str()).collect::<Vec<_>>(), ["1", "2", "3", "4", "5"]);
        assert_eq!(sus.anchors, Some(["Strongly disagree".to_string(), "Strongly agree".to_string()]));
        assert!(!rating.multi && !rating.typed && rating.max_chars.is_none());
    }

    #[test]
    fn a_likert_item_with_a_word_for_every_point_shows_the_words() {
        let five = words(&["Strongly disagree", "Disagree", "Neutral", "Agree", "Strongly agree"]);
        let l = item(ItemKind::Likert { points: 5, anchors: five.clone() });
        assert_eq!(pairs(&l), (1..=5).zip(five).map(|(v, w)| (Value::from(v), w)).collect::<Vec<_>>());
        assert_eq!(l.anchors, None, "a word on every point needs no anchors");
        let two = item(ItemKind::Likert { points: 2, anchors: words(&["No", "Yes"]) });
        assert_eq!(two.options.iter().map(|o| o.label.as_str()).collect::<Vec<_>>(), ["1", "2"], "two words on two points are its ends");
    }

    #[test]
    fn choices_yes_no_and_text() {
        let one = item(ItemKind::Single { choices: words(&["a", "b"]) });
        assert_eq!(pairs(&one), vec![(Value::from("a"), "a".to_string()), (Value::from("b"), "b".to_string())]);
        assert!(!one.multi);
        assert!(item(ItemKind::Multiple { choices: words(&["a"]) }).multi);
        let yn = item(ItemKind::YesNo);
        assert_eq!(pairs(&yn), vec![(Value::Bool(true), "Yes".to_string()), (Value::Bool(false), "No".to_string())]);
        let text = item(ItemKind::Text { max_chars: 300 });
        assert!(text.typed && text.options.is_empty());
        assert_eq!(text.max_chars, Some(300));
    }

    #[test]
    fn the_item_keeps_its_fields_beside_what_it_takes() {
        let json = serde_json::to_value(item(ItemKind::Text { max_chars: 9 })).unwrap();
        assert_eq!(json["id"], "q");
        assert_eq!(json["kind"], serde_json::json!({"Text": {"max_chars": 9}}));
        assert_eq!(json["required"], true);
        assert_eq!(json["typed"], true);
    }
}
