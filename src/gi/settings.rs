//! A method's settings as data: names, kinds, ranges and defaults declared once, from which the
//! command line's flags, the viewer's keys, the report's grid and the validation (one clear
//! error line) all follow.

use std::fmt;

use serde::Serialize;

use crate::error::InputError;

/// What values a setting takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// A whole number in `min..=max`.
    Int { min: i64, max: i64 },
    /// A finite number in `[min, max]`.
    Float { min: f64, max: f64 },
    /// On when the flag is given.
    Flag,
    /// One of the listed words.
    Choice(&'static [&'static str]),
    /// Free text the method parses itself (e.g. "fit" or "R,G,B").
    Text,
}

/// Keys that step a setting in the viewer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Keys {
    pub decrease: char,
    pub increase: char,
    /// How far one press moves the value.
    pub step: f64,
}

/// One setting of a method.
#[derive(Clone, Copy, Debug)]
pub struct Setting {
    /// The command-line flag without its dashes (`lattice` is `--lattice`).
    pub name: &'static str,
    pub help: &'static str,
    pub kind: Kind,
    /// The default, written as a user would write it (empty for a flag that is off).
    pub default: &'static str,
    /// Keys that step it in the viewer (shown in the overlay and the help).
    pub keys: Option<Keys>,
    /// Values `vkgi report` sweeps when the user names none (empty: the default only).
    pub sweep: &'static [&'static str],
    /// (approximate, exact): a value that trades accuracy for time against the value it
    /// approximates; `vkgi report` scores each row at the first against the row of the same
    /// configuration at the second.
    pub approximates: Option<(&'static str, &'static str)>,
}

impl Setting {
    /// A setting with no viewer keys and no sweep.
    pub const fn new(
        name: &'static str,
        kind: Kind,
        default: &'static str,
        help: &'static str,
    ) -> Self {
        Setting {
            name,
            help,
            kind,
            default,
            keys: None,
            sweep: &[],
            approximates: None,
        }
    }

    pub const fn keys(mut self, decrease: char, increase: char, step: f64) -> Self {
        self.keys = Some(Keys {
            decrease,
            increase,
            step,
        });
        self
    }

    pub const fn sweep(mut self, values: &'static [&'static str]) -> Self {
        self.sweep = values;
        self
    }

    /// Value `approximate` approximates value `exact` (see [`Setting::approximates`]).
    pub const fn approximating(mut self, approximate: &'static str, exact: &'static str) -> Self {
        self.approximates = Some((approximate, exact));
        self
    }

    /// Parse `text` as this setting's value, checking its range.
    pub fn parse(&self, text: &str) -> Result<Value, InputError> {
        let bad = |why: String| InputError::new(format!("--{} {text}: {why}", self.name));
        let text = text.trim();
        match self.kind {
            Kind::Int { min, max } => {
                let v: i64 = text.parse().map_err(|_| bad("not a whole number".into()))?;
                if !(min..=max).contains(&v) {
                    return Err(bad(format!("out of range {min}..={max}")));
                }
                Ok(Value::Int(v))
            }
            Kind::Float { min, max } => {
                let v: f64 = text.parse().map_err(|_| bad("not a number".into()))?;
                if !(v.is_finite() && (min..=max).contains(&v)) {
                    return Err(bad(format!("out of range [{min}, {max}]")));
                }
                Ok(Value::Float(v))
            }
            Kind::Flag => match text {
                "" | "true" | "on" | "1" => Ok(Value::Flag(true)),
                "false" | "off" | "0" => Ok(Value::Flag(false)),
                _ => Err(bad("not on or off".into())),
            },
            Kind::Choice(words) => words
                .iter()
                .find(|w| w.eq_ignore_ascii_case(text))
                .map(|w| Value::Text((*w).to_string()))
                .ok_or_else(|| bad(format!("not one of {}", words.join(", ")))),
            Kind::Text => Ok(Value::Text(text.to_string())),
        }
    }

    /// The default value.
    pub fn default_value(&self) -> Result<Value, InputError> {
        match self.kind {
            Kind::Flag if self.default.is_empty() => Ok(Value::Flag(false)),
            _ => self.parse(self.default),
        }
    }

    /// `value` moved by `presses` steps of the viewer keys, clamped to the range.
    pub fn stepped(&self, value: &Value, presses: f64) -> Value {
        let step = self.keys.map_or(1.0, |k| k.step) * presses;
        match (self.kind, value) {
            (Kind::Int { min, max }, Value::Int(v)) => {
                Value::Int((*v + step.round() as i64).clamp(min, max))
            }
            (Kind::Float { min, max }, Value::Float(v)) => {
                // Round to the step's grid so repeated presses do not drift.
                let stepped = ((v + step) / step.abs()).round() * step.abs();
                Value::Float(stepped.clamp(min, max))
            }
            (Kind::Choice(words), Value::Text(t)) => {
                let at = words.iter().position(|w| w == t).unwrap_or(0) as i64;
                let n = words.len() as i64;
                let next = (at + step.round() as i64).rem_euclid(n.max(1));
                Value::Text(words[next as usize].to_string())
            }
            (Kind::Flag, Value::Flag(on)) => Value::Flag(!on),
            _ => value.clone(),
        }
    }
}

/// A setting's value.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Value {
    Int(i64),
    Float(f64),
    Flag(bool),
    Text(String),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Int(v) => write!(f, "{v}"),
            Value::Float(v) => write!(f, "{v}"),
            Value::Flag(v) => write!(f, "{}", if *v { "on" } else { "off" }),
            Value::Text(v) => write!(f, "{v}"),
        }
    }
}

/// The values of one method's settings.
#[derive(Clone, Debug, Serialize)]
pub struct Settings {
    #[serde(skip)]
    specs: &'static [Setting],
    values: Vec<(&'static str, Value)>,
}

impl Settings {
    /// Every setting at its default.
    pub fn defaults(specs: &'static [Setting]) -> Result<Settings, InputError> {
        let values = specs
            .iter()
            .map(|s| Ok((s.name, s.default_value()?)))
            .collect::<Result<_, InputError>>()?;
        Ok(Settings { specs, values })
    }

    /// The declarations of these settings.
    pub fn specs(&self) -> &'static [Setting] {
        self.specs
    }

    /// Whether `name` is one of these settings.
    pub fn has(&self, name: &str) -> bool {
        self.specs.iter().any(|s| s.name == name)
    }

    /// Set `name` from the user's `text` (validated).
    pub fn set(&mut self, name: &str, text: &str) -> Result<(), InputError> {
        let spec =
            self.specs.iter().find(|s| s.name == name).ok_or_else(|| {
                InputError::new(format!("--{name} is not a setting of this method"))
            })?;
        let value = spec.parse(text)?;
        self.set_value(name, value);
        Ok(())
    }

    /// Set `name` to an already validated value.
    pub fn set_value(&mut self, name: &str, value: Value) {
        if let Some(entry) = self.values.iter_mut().find(|(n, _)| *n == name) {
            entry.1 = value;
        }
    }

    pub fn get(&self, name: &str) -> Option<&Value> {
        self.values.iter().find(|(n, _)| *n == name).map(|(_, v)| v)
    }

    /// Every (name, value), in declaration order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, &Value)> {
        self.values.iter().map(|(n, v)| (*n, v))
    }

    fn missing(name: &str, wanted: &str) -> InputError {
        InputError::new(format!("setting '{name}' is not a {wanted} of this method"))
    }

    pub fn int(&self, name: &str) -> Result<i64, InputError> {
        match self.get(name) {
            Some(Value::Int(v)) => Ok(*v),
            _ => Err(Self::missing(name, "whole number")),
        }
    }

    /// A whole-number setting whose declared range fits a `u32`.
    pub fn u32(&self, name: &str) -> Result<u32, InputError> {
        let v = self.int(name)?;
        u32::try_from(v).map_err(|_| Self::missing(name, "non-negative 32-bit number"))
    }

    pub fn float(&self, name: &str) -> Result<f64, InputError> {
        match self.get(name) {
            Some(Value::Float(v)) => Ok(*v),
            _ => Err(Self::missing(name, "number")),
        }
    }

    pub fn flag(&self, name: &str) -> Result<bool, InputError> {
        match self.get(name) {
            Some(Value::Flag(v)) => Ok(*v),
            _ => Err(Self::missing(name, "flag")),
        }
    }

    pub fn text(&self, name: &str) -> Result<&str, InputError> {
        match self.get(name) {
            Some(Value::Text(v)) => Ok(v),
            _ => Err(Self::missing(name, "word")),
        }
    }

    /// "name value" pairs for the settings that have viewer keys (the overlay's line).
    pub fn keyed_summary(&self) -> String {
        self.specs
            .iter()
            .filter(|s| s.keys.is_some())
            .filter_map(|s| self.get(s.name).map(|v| format!("{} {}", s.name, short(v))))
            .collect::<Vec<_>>()
            .join("  ")
    }
}

/// A value written briefly (floats with at most 3 decimals).
fn short(value: &Value) -> String {
    match value {
        Value::Float(v) => {
            let text = format!("{v:.3}");
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        }
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECS: &[Setting] = &[
        Setting::new("cells", Kind::Int { min: 2, max: 64 }, "10", "cells").keys('[', ']', 2.0),
        Setting::new(
            "lambda",
            Kind::Float {
                min: 0.0,
                max: 0.999,
            },
            "0.5",
            "λ",
        )
        .keys('-', '=', 0.05),
        Setting::new("naive", Kind::Flag, "", "naive kernel"),
        Setting::new("mode", Kind::Choice(&["fast", "exact"]), "fast", "mode"),
    ];

    #[test]
    fn defaults_parse_and_values_are_range_checked() {
        let mut s = match Settings::defaults(SPECS) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(s.u32("cells").ok(), Some(10));
        assert_eq!(s.flag("naive").ok(), Some(false));
        assert!(
            s.set("cells", "65")
                .is_err_and(|e| e.0.contains("out of range 2..=64"))
        );
        assert!(s.set("cells", "-1").is_err());
        assert!(s.set("lambda", "NaN").is_err());
        assert!(s.set("lambda", "1e30").is_err());
        assert!(
            s.set("mode", "slow")
                .is_err_and(|e| e.0.contains("fast, exact"))
        );
        assert!(s.set("mode", "EXACT").is_ok());
        assert_eq!(s.text("mode").ok(), Some("exact"));
        assert!(s.set("nothing", "1").is_err());
        assert!(
            s.float("cells").is_err(),
            "wrong kind is an error, not a panic"
        );
    }

    #[test]
    fn viewer_steps_stay_in_range_and_on_the_grid() {
        let lambda = &SPECS[1];
        let mut v = Value::Float(0.5);
        for _ in 0..3 {
            v = lambda.stepped(&v, 1.0);
        }
        assert!(
            matches!(v, Value::Float(x) if (x - 0.65).abs() < 1e-12),
            "{v:?}"
        );
        assert_eq!(
            lambda.stepped(&Value::Float(0.98), 1.0),
            Value::Float(0.999)
        );
        assert_eq!(SPECS[0].stepped(&Value::Int(3), -1.0), Value::Int(2));
        assert_eq!(
            SPECS[3].stepped(&Value::Text("exact".into()), 1.0),
            Value::Text("fast".into())
        );
    }
}
