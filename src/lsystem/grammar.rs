//! L-system grammars: the axiom, the rules (context-free, stochastic or parametric), the turtle's
//! angle, step and width, and the grammar file format (see `docs/lsystem.md`).
//!
//! Every symbol is one ASCII byte: a letter (`A`–`Z`, `a`–`z`) or a turtle command
//! (`+ - & ^ \ / | [ ] !`). A symbol has the same number of parameters everywhere it appears in
//! one grammar; parameters live in a side array (see `derive`).

use super::error::LsystemError;
use super::expr::Expr;

/// The turtle commands, besides letters.
pub const COMMANDS: &[u8] = b"+-&^\\/|[]!";

/// Whether `c` is a symbol: a letter or a turtle command.
pub fn is_symbol(c: u8) -> bool {
    c.is_ascii_alphabetic() || COMMANDS.contains(&c)
}

/// One rule: `pred(params) [: cond] [-(weight)]-> successor`.
#[derive(Clone, Debug)]
pub struct Rule {
    /// The predecessor symbol.
    pub pred: u8,
    /// The condition (parametric rules), true when absent.
    pub cond: Option<Expr>,
    /// The weight of a stochastic rule (1 when not given).
    pub weight: f32,
    /// Whether a weight was written.
    pub weighted: bool,
    /// The successor's symbols.
    pub succ: Vec<u8>,
    /// The successor's parameter expressions, in order (each symbol's arity many).
    pub args: Vec<Expr>,
}

/// How a symbol is rewritten.
#[derive(Clone, Debug, PartialEq)]
pub enum Choice {
    /// No rule: the symbol stays as it is.
    Identity,
    /// One rule without a condition.
    Single(u32),
    /// Several rules without conditions: `(threshold, rule)` pairs; a 24-bit random number `h`
    /// picks the first rule with `h < threshold` (the last threshold is 2^24).
    Stochastic(Vec<(u32, u32)>),
    /// Rules with conditions, tried in order; the first whose condition holds applies, and the
    /// symbol stays as it is when none does.
    Conditional(Vec<u32>),
}

/// A parsed, checked grammar.
#[derive(Clone, Debug)]
pub struct Grammar {
    /// A name, for reports and model files.
    pub name: String,
    /// The axiom's symbols.
    pub axiom: Vec<u8>,
    /// The axiom's parameters (constants).
    pub axiom_params: Vec<f32>,
    /// The rules in file order.
    pub rules: Vec<Rule>,
    /// Parameters per symbol.
    pub arity: [u8; 128],
    /// How each symbol is rewritten.
    pub choice: Vec<Choice>,
    /// The turning angle, degrees.
    pub angle_deg: f32,
    /// The length of `F` and `f` without a parameter, metres.
    pub step: f32,
    /// The initial width of the line, metres.
    pub width: f32,
    /// The factor `!` without a parameter multiplies the width by.
    pub width_factor: f32,
    /// The species whose bark and leaf textures a model uses.
    pub species: String,
    /// The derivation count used when none is given.
    pub n: u32,
    /// The height of a model, metres, when none is given.
    pub height: f32,
}

/// The unchecked parts of a grammar, as written in a file or on the command line.
#[derive(Clone, Debug)]
pub struct Source {
    /// Name.
    pub name: String,
    /// Axiom text, e.g. `F(1)A`.
    pub axiom: String,
    /// Rule texts, e.g. `F(l) -> F(l*0.8)[+F(l*0.6)]`.
    pub rules: Vec<String>,
    /// Angle, degrees.
    pub angle_deg: f32,
    /// Step, metres.
    pub step: f32,
    /// Width, metres.
    pub width: f32,
    /// Width factor of `!`.
    pub width_factor: f32,
    /// Species of the textures.
    pub species: String,
    /// Default derivation count.
    pub n: u32,
    /// Default model height, metres.
    pub height: f32,
}

impl Default for Source {
    fn default() -> Source {
        Source {
            name: "lsystem".into(),
            axiom: String::new(),
            rules: Vec::new(),
            angle_deg: 25.0,
            step: 1.0,
            width: 0.1,
            width_factor: 0.7,
            species: "broadleaf".into(),
            n: 4,
            height: 6.0,
        }
    }
}

/// The species whose textures a model may use.
pub const SPECIES: [&str; 4] = ["broadleaf", "conifer", "birch", "shrub"];

/// A module as written: a symbol and its argument texts.
struct Written {
    sym: u8,
    args: Vec<String>,
}

/// Splits `text` into modules, checking every character.
fn modules(text: &str, what: &str) -> Result<Vec<Written>, LsystemError> {
    modules_of(text).map_err(|e| e.at(what))
}

/// [`modules`] without the part's name in the error.
fn modules_of(text: &str) -> Result<Vec<Written>, LsystemError> {
    let s = text.as_bytes();
    let mut out: Vec<Written> = Vec::new();
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if c == b'(' {
            let Some(last) = out.last_mut() else {
                return Err(LsystemError::ParenAfterNothing(i + 1));
            };
            if last.sym == b'[' || last.sym == b']' {
                return Err(LsystemError::BracketParameters(last.sym as char));
            }
            if !last.args.is_empty() {
                return Err(LsystemError::SecondParameterList(i + 1));
            }
            // Find the matching ')', then split at top-level commas.
            let (mut depth, mut j, mut start) = (0usize, i + 1, i + 1);
            let mut args = Vec::new();
            loop {
                let Some(&d) = s.get(j) else {
                    return Err(LsystemError::Unclosed(i + 1));
                };
                match d {
                    b'(' => depth += 1,
                    b')' if depth == 0 => {
                        args.push(text[start..j].trim().to_string());
                        break;
                    }
                    b')' => depth -= 1,
                    b',' if depth == 0 => {
                        args.push(text[start..j].trim().to_string());
                        start = j + 1;
                    }
                    _ => {}
                }
                j += 1;
            }
            if args.iter().any(|a| a.is_empty()) {
                return Err(LsystemError::EmptyParameter(i + 1));
            }
            last.args = args;
            i = j + 1;
            continue;
        }
        if !is_symbol(c) {
            let ch = text[i..].chars().next().unwrap_or('?');
            return Err(LsystemError::NotSymbol { ch, column: i + 1 });
        }
        out.push(Written { sym: c, args: Vec::new() });
        i += 1;
    }
    Ok(out)
}

fn check_brackets(syms: &[u8], what: &str) -> Result<(), LsystemError> {
    let mut depth = 0i64;
    for &c in syms {
        match c {
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth < 0 {
                    return Err(LsystemError::UnmatchedClose.at(what));
                }
            }
            _ => {}
        }
    }
    if depth != 0 {
        return Err(LsystemError::UnmatchedOpen(depth).at(what));
    }
    Ok(())
}

fn set_arity(arity: &mut [Option<u8>; 128], sym: u8, n: usize, what: &str) -> Result<(), LsystemError> {
    if n > 8 {
        return Err(LsystemError::TooManyParameters { sym: sym as char, n }.at(what));
    }
    match arity[sym as usize] {
        None => arity[sym as usize] = Some(n as u8),
        Some(a) if a as usize == n => {}
        Some(a) => return Err(LsystemError::Arity { sym: sym as char, n, elsewhere: a }.at(what)),
    }
    Ok(())
}

impl Grammar {
    /// Checks and compiles a grammar source.
    pub fn compile(src: &Source) -> Result<Grammar, LsystemError> {
        if !(src.angle_deg.is_finite()
            && src.step.is_finite()
            && src.step > 0.0
            && src.width.is_finite()
            && src.width >= 0.0)
        {
            return Err(LsystemError::Turtle);
        }
        if !(src.width_factor.is_finite() && src.width_factor > 0.0) {
            return Err(LsystemError::WidthFactor);
        }
        if !(src.height.is_finite() && src.height > 0.0) {
            return Err(LsystemError::Height);
        }
        if !SPECIES.contains(&src.species.as_str()) {
            return Err(LsystemError::Species { name: src.species.clone(), known: SPECIES.join(", ") });
        }
        let mut arity: [Option<u8>; 128] = [None; 128];
        let axiom_mods = modules(&src.axiom, "axiom")?;
        if axiom_mods.is_empty() {
            return Err(LsystemError::EmptyAxiom);
        }
        let mut axiom = Vec::new();
        let mut axiom_params = Vec::new();
        for m in &axiom_mods {
            set_arity(&mut arity, m.sym, m.args.len(), "axiom")?;
            axiom.push(m.sym);
            for a in &m.args {
                let e = Expr::parse(a, &[]).map_err(|e| LsystemError::Expr(e).at("axiom"))?;
                axiom_params.push(e.eval(&[]));
            }
        }
        check_brackets(&axiom, "axiom")?;

        let mut rules = Vec::new();
        for (k, text) in src.rules.iter().enumerate() {
            let what = format!("rule {} '{}'", k + 1, text.trim());
            let (lhs, rhs) = if let Some(p) = text.find("->") {
                (&text[..p], &text[p + 2..])
            } else if let Some(p) = text.find('=') {
                (&text[..p], &text[p + 1..])
            } else {
                return Err(LsystemError::NoArrow.at(what));
            };
            let mut lhs = lhs.trim_end();
            // A stochastic weight: `-(0.33)` just before the arrow.
            let mut weight = 1.0f32;
            let mut weighted = false;
            if lhs.ends_with(')')
                && let Some(p) = lhs.rfind("-(")
            {
                let w = &lhs[p + 2..lhs.len() - 1];
                let before = lhs[..p].trim_end();
                if !before.is_empty() && !before.ends_with(':') {
                    weight = w
                        .trim()
                        .parse::<f32>()
                        .map_err(|_| LsystemError::WeightNotNumber(w.trim().to_string()).at(&what))?;
                    weighted = true;
                    lhs = before;
                }
            }
            if !(weight.is_finite() && weight >= 0.0) {
                return Err(LsystemError::Weight.at(what));
            }
            let (pred_text, cond_text) = match lhs.find(':') {
                Some(p) => (&lhs[..p], Some(lhs[p + 1..].trim())),
                None => (lhs, None),
            };
            let pred_mods = modules(pred_text, &what)?;
            if pred_mods.len() != 1 {
                return Err(LsystemError::Predecessor.at(what));
            }
            let pred = &pred_mods[0];
            if pred.sym == b'[' || pred.sym == b']' {
                return Err(LsystemError::RewriteBracket.at(what));
            }
            set_arity(&mut arity, pred.sym, pred.args.len(), &what)?;
            let names = pred.args.clone();
            for (i, n) in names.iter().enumerate() {
                let ok = n.bytes().next().is_some_and(|c| c.is_ascii_alphabetic() || c == b'_')
                    && n.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_');
                if !ok {
                    return Err(LsystemError::ParameterNotName(n.clone()).at(what));
                }
                if names[..i].contains(n) {
                    return Err(LsystemError::ParameterTwice(n.clone()).at(what));
                }
            }
            let cond = match cond_text {
                Some(c) => Some(Expr::parse(c, &names).map_err(|e| LsystemError::Expr(e).at(&what))?),
                None => None,
            };
            let mut succ = Vec::new();
            let mut args = Vec::new();
            for m in modules(rhs, &what)? {
                set_arity(&mut arity, m.sym, m.args.len(), &what)?;
                succ.push(m.sym);
                for a in &m.args {
                    args.push(Expr::parse(a, &names).map_err(|e| LsystemError::Expr(e).at(&what))?);
                }
            }
            check_brackets(&succ, &what)?;
            rules.push(Rule { pred: pred.sym, cond, weight, weighted, succ, args });
        }

        // Decide how each symbol is rewritten.
        let mut choice = vec![Choice::Identity; 128];
        for (s, slot) in choice.iter_mut().enumerate() {
            let idx: Vec<u32> = (0..rules.len() as u32).filter(|&i| rules[i as usize].pred as usize == s).collect();
            if idx.is_empty() {
                continue;
            }
            let conditional = idx.iter().any(|&i| rules[i as usize].cond.is_some());
            if conditional {
                if idx.iter().any(|&i| rules[i as usize].weighted) {
                    return Err(LsystemError::WeightWithCondition(s as u8 as char));
                }
                *slot = Choice::Conditional(idx);
            } else if idx.len() == 1 && !rules[idx[0] as usize].weighted {
                *slot = Choice::Single(idx[0]);
            } else {
                let total: f64 = idx.iter().map(|&i| rules[i as usize].weight as f64).sum();
                if !(total > 0.0 && total.is_finite()) {
                    return Err(LsystemError::WeightSum(s as u8 as char));
                }
                let mut cum = 0.0f64;
                let mut table = Vec::new();
                for (k, &i) in idx.iter().enumerate() {
                    cum += rules[i as usize].weight as f64;
                    let t = if k + 1 == idx.len() {
                        1u32 << 24
                    } else {
                        ((cum / total) * (1u32 << 24) as f64).round() as u32
                    };
                    table.push((t.min(1 << 24), i));
                }
                *slot = Choice::Stochastic(table);
            }
        }
        let mut ar = [0u8; 128];
        for (a, o) in ar.iter_mut().zip(arity.iter()) {
            *a = o.unwrap_or(0);
        }
        Ok(Grammar {
            name: src.name.clone(),
            axiom,
            axiom_params,
            rules,
            arity: ar,
            choice,
            angle_deg: src.angle_deg,
            step: src.step,
            width: src.width,
            width_factor: src.width_factor,
            species: src.species.clone(),
            n: src.n,
            height: src.height,
        })
    }

    /// Parses and compiles a grammar file's text (`origin` names it in errors).
    pub fn parse_file(text: &str, origin: &str) -> Result<Grammar, LsystemError> {
        let mut src = Source { name: String::new(), ..Source::default() };
        let mut have_axiom = false;
        for (ln, raw) in text.lines().enumerate() {
            let line = match raw.find('#') {
                Some(p) => &raw[..p],
                None => raw,
            }
            .trim();
            if line.is_empty() {
                continue;
            }
            let at = || format!("{origin} line {}", ln + 1);
            let Some((key, value)) = line.split_once(':') else {
                return Err(LsystemError::KeyValue.at(at()));
            };
            let value = value.trim();
            let num = |v: &str| {
                v.parse::<f32>().map_err(|error| LsystemError::NotNumber { value: v.to_string(), error }.at(at()))
            };
            match key.trim() {
                "name" => src.name = value.to_string(),
                "axiom" => {
                    src.axiom = value.to_string();
                    have_axiom = true;
                }
                "rule" => src.rules.push(value.to_string()),
                "angle" => src.angle_deg = num(value)?,
                "step" => src.step = num(value)?,
                "width" => src.width = num(value)?,
                "width-factor" => src.width_factor = num(value)?,
                "species" => src.species = value.to_string(),
                "height" => src.height = num(value)?,
                "n" => {
                    src.n = value
                        .parse()
                        .map_err(|error| LsystemError::NotCount { value: value.to_string(), error }.at(at()))?
                }
                other => return Err(LsystemError::UnknownKey(other.to_string()).at(at())),
            }
        }
        if !have_axiom {
            return Err(LsystemError::NoAxiom.at(origin));
        }
        if src.name.is_empty() {
            src.name =
                std::path::Path::new(origin).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        }
        Grammar::compile(&src).map_err(|e| e.at(origin))
    }

    /// Whether any symbol carries parameters.
    pub fn is_parametric(&self) -> bool {
        self.arity.iter().any(|&a| a > 0)
    }

    /// Whether any symbol has conditional rules.
    pub fn is_conditional(&self) -> bool {
        self.choice.iter().any(|c| matches!(c, Choice::Conditional(_)))
    }

    /// The longest successor, in symbols (1 for a symbol without rules).
    pub fn max_successor(&self) -> usize {
        self.rules.iter().map(|r| r.succ.len()).max().unwrap_or(1).max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g(axiom: &str, rules: &[&str]) -> Result<Grammar, LsystemError> {
        Grammar::compile(&Source {
            axiom: axiom.into(),
            rules: rules.iter().map(|s| s.to_string()).collect(),
            ..Source::default()
        })
    }

    #[test]
    fn rules_of_every_kind_parse() {
        let gr = g("F(1)A", &["F(l) -> F(l*0.8)[+F(l*0.6)]", "A -(0.3)-> AB", "A -(0.7)-> B", "B(x): x > 1 -> B(x-1)"]);
        // B has a parameter in its rule but none in A's successors: a mismatch.
        assert!(gr.is_err());
        let gr = g("F(1)A", &["F(l) -> F(l*0.8)[+F(l*0.6)]", "A -(0.25)-> AB", "A -(0.75)-> B"]).unwrap();
        assert_eq!(gr.arity[b'F' as usize], 1);
        assert_eq!(gr.axiom_params, vec![1.0]);
        match &gr.choice[b'A' as usize] {
            Choice::Stochastic(t) => assert_eq!(t.iter().map(|x| x.0).collect::<Vec<_>>(), vec![1 << 22, 1 << 24]),
            c => panic!("{c:?}"),
        }
        assert_eq!(gr.choice[b'B' as usize], Choice::Identity);
    }
}
