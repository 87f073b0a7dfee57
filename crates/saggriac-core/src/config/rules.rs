//! A parameter's rule as data (as scikit-learn's `_parameter_constraints`): each teacher's
//! parameter file lists its parameters with their rules (`TeacherParams::RULES`), `validate()`
//! checks each value against its entry, and the binding tells a value of the wrong type the same
//! text, so that one bad value is told one rule by every route (a selector, `Config`, a TOML
//! file, `--set`). Rules between parameters (p_alp + p_random <= 1) stay in `validate()`.

use crate::error::{invalid, Num, Result, MAX_COUNT};

/// What a parameter's value must be.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rule {
    /// An int in [lo, hi].
    Int(usize, usize),
    /// A finite float in [lo, hi], each end included or not, with a note on its unit or meaning
    /// ("" for none). An infinite `hi` is an open upper end ("a finite float >= lo").
    Float { lo: f64, lo_in: bool, hi: f64, hi_in: bool, note: &'static str },
    /// A finite float with |value| <= 1e100: a threshold in the units of the competences told.
    Finite,
    /// A bool.
    Bool,
    /// One of the names of a choice (serde checks it and names the choices).
    Choice,
}

/// An int in [1, MAX_COUNT]: a count the core allocates for.
pub const COUNT: Rule = Rule::Int(1, MAX_COUNT);
/// A float in [0, 1].
pub const PROBABILITY: Rule = Rule::Float { lo: 0.0, lo_in: true, hi: 1.0, hi_in: true, note: "" };
/// A finite float > 0.
pub const POSITIVE: Rule = Rule::Float { lo: 0.0, lo_in: false, hi: f64::INFINITY, hi_in: false, note: "" };

/// A float in (lo, hi].
pub const fn open_closed(lo: f64, hi: f64) -> Rule {
    Rule::Float { lo, lo_in: false, hi, hi_in: true, note: "" }
}

impl Rule {
    /// The rule as a message states it ("an int in [1, 1000000]").
    pub fn text(&self) -> String {
        match *self {
            Rule::Int(lo, hi) => format!("an int in [{lo}, {hi}]"),
            Rule::Float { lo, lo_in, hi, hi_in, note } => {
                let range = if hi.is_infinite() {
                    format!("a finite float {} {}", if lo_in { ">=" } else { ">" }, Num(lo))
                } else {
                    format!("a float in {}{}, {}{}", if lo_in { "[" } else { "(" }, Num(lo), Num(hi), if hi_in { "]" } else { ")" })
                };
                if note.is_empty() {
                    range
                } else {
                    format!("{range} ({note})")
                }
            }
            Rule::Finite => "a finite float with |value| <= 1e100".into(),
            Rule::Bool => "a bool".into(),
            Rule::Choice => "one of its choices".into(),
        }
    }

    /// The rule of a parameter also taken per dimension, as a message states it for a list:
    /// each value meets the single number's rule.
    pub fn per_dimension_text(&self) -> String {
        format!("{}, or a list of such floats, one per dimension of the box", self.text())
    }

    /// Whether the float `v` meets the rule (never for a rule of ints, bools or choices).
    pub fn holds_float(&self, v: f64) -> bool {
        match *self {
            Rule::Float { lo, lo_in, hi, hi_in, .. } => v.is_finite() && (v > lo || (lo_in && v == lo)) && (v < hi || (hi_in && v == hi)),
            Rule::Finite => v.is_finite() && v.abs() <= 1e100,
            _ => false,
        }
    }
}

/// `name`'s entry in `rules` (every parameter a `validate()` checks has one).
pub fn rule_of(rules: &[(&'static str, Rule)], name: &str) -> Option<Rule> {
    rules.iter().find(|r| r.0 == name).map(|r| r.1)
}

fn listed(rules: &[(&'static str, Rule)], name: &str) -> Rule {
    rule_of(rules, name).unwrap_or_else(|| panic!("the parameter '{name}' has no entry in its RULES"))
}

/// The int parameter `name` = `v` against its rule in `rules`.
pub fn check_int(owner: &'static str, rules: &[(&'static str, Rule)], name: &str, v: usize) -> Result<()> {
    match listed(rules, name) {
        Rule::Int(lo, hi) if (lo..=hi).contains(&v) => Ok(()),
        rule => Err(invalid(owner, name, rule.text(), v)),
    }
}

/// The float parameter `name` = `v` against its rule in `rules`.
pub fn check_float(owner: &'static str, rules: &[(&'static str, Rule)], name: &str, v: f64) -> Result<()> {
    let rule = listed(rules, name);
    if rule.holds_float(v) {
        Ok(())
    } else {
        Err(invalid(owner, name, rule.text(), Num(v)))
    }
}

/// Checks each listed field of `$p` against its rule in `$rules`, in order, as
/// `check_int`/`check_float` (`int name` or `float name`; the field's name is the parameter's).
macro_rules! check_fields {
    ($owner:expr, $rules:expr, $p:expr, $($kind:ident $field:ident),+ $(,)?) => {{
        $($crate::config::rules::check_fields!(@one $owner, $rules, $p, $kind $field);)+
    }};
    (@one $o:expr, $r:expr, $p:expr, int $f:ident) => {
        $crate::config::rules::check_int($o, $r, stringify!($f), $p.$f)?
    };
    (@one $o:expr, $r:expr, $p:expr, float $f:ident) => {
        $crate::config::rules::check_float($o, $r, stringify!($f), $p.$f)?
    };
}
pub(crate) use check_fields;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_read_as_their_checks() {
        assert_eq!(COUNT.text(), "an int in [1, 1000000]");
        assert_eq!(PROBABILITY.text(), "a float in [0, 1]");
        assert_eq!(POSITIVE.text(), "a finite float > 0");
        assert_eq!(open_closed(0.0, 0.5).text(), "a float in (0, 0.5]");
        let r = [("a", POSITIVE), ("b", open_closed(0.0, 1.0)), ("c", Rule::Finite), ("n", COUNT)];
        assert!(check_float("X", &r, "a", 0.0).is_err() && check_float("X", &r, "a", 1e-300).is_ok());
        assert!(check_float("X", &r, "a", f64::INFINITY).is_err() && check_float("X", &r, "a", f64::NAN).is_err());
        assert!(check_float("X", &r, "b", 1.0).is_ok() && check_float("X", &r, "b", 0.0).is_err());
        assert!(check_float("X", &r, "c", -1e100).is_ok() && check_float("X", &r, "c", 1e101).is_err());
        let e = check_int("X", &r, "n", 0).unwrap_err().to_string();
        assert_eq!(e, "The 'n' parameter of X must be an int in [1, 1000000]. Got 0 instead.");
    }
}
