//! Case parameters: documentation ([`ParamInfo`]), the [`CaseParams`] trait and the
//! [`ParamCase`] wrapper that turns a parameter struct and a run function into a
//! [`Case`], and `--set KEY=VALUE` overrides ([`Override`], [`apply_overrides`]).

use std::collections::BTreeSet;
use std::fmt;
use std::str::FromStr;

use anyhow::{Context, anyhow, bail};
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;

use crate::case::{Case, CaseOutput, Mode, RunContext};

/// Documentation of one parameter, shown by `cargo xtask list`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamInfo {
    /// The field name (the `--set` key).
    pub name: &'static str,
    /// SI unit (`"m"`, `"s"`, `"kg/m^3"`), or `"-"` when dimensionless.
    pub unit: &'static str,
    /// What the parameter means, in a few words.
    pub meaning: &'static str,
}

impl ParamInfo {
    /// A parameter description (usable in a `const` table).
    pub const fn new(name: &'static str, unit: &'static str, meaning: &'static str) -> Self {
        Self {
            name,
            unit,
            meaning,
        }
    }
}

/// A parameter struct of a case. `Default` is the published or analytic setup.
///
/// Overrides are checked against the current values, so unknown `--set` keys are
/// rejected before deserialization (`#[serde(deny_unknown_fields)]` is not needed).
pub trait CaseParams: Serialize + DeserializeOwned + Default + Clone + Send + 'static {
    /// One entry per field, in declaration order.
    const INFO: &'static [ParamInfo];

    /// Adjusts the parameters to a [`Mode`] (e.g. a shorter horizon for
    /// [`Mode::Quick`]). Called before `--set` overrides. The default does nothing.
    fn apply_mode(&mut self, _mode: Mode) {}
}

/// The run function of a [`ParamCase`].
pub type RunFn<P> = fn(&P, &RunContext) -> anyhow::Result<CaseOutput>;

/// A [`Case`] made of a name, an area, a description, a parameter struct and a run
/// function; the parameter plumbing (`params_json`, `set_params_json`, `apply_mode`,
/// `param_info`) comes for free.
pub struct ParamCase<P: CaseParams> {
    name: &'static str,
    area: &'static str,
    description: &'static str,
    params: P,
    run: RunFn<P>,
}

impl<P: CaseParams> ParamCase<P> {
    /// A case with the default parameters.
    pub fn new(
        name: &'static str,
        area: &'static str,
        description: &'static str,
        run: RunFn<P>,
    ) -> Self {
        Self {
            name,
            area,
            description,
            params: P::default(),
            run,
        }
    }

    /// [`ParamCase::new`], boxed for the registry.
    pub fn boxed(
        name: &'static str,
        area: &'static str,
        description: &'static str,
        run: RunFn<P>,
    ) -> Box<dyn Case> {
        Box::new(Self::new(name, area, description, run))
    }

    /// The current parameters.
    pub fn params(&self) -> &P {
        &self.params
    }
}

impl<P: CaseParams> Case for ParamCase<P> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn area(&self) -> &'static str {
        self.area
    }
    fn description(&self) -> &'static str {
        self.description
    }
    fn param_info(&self) -> Vec<ParamInfo> {
        P::INFO.to_vec()
    }
    fn params_json(&self) -> Value {
        serde_json::to_value(&self.params).unwrap_or(Value::Null)
    }
    fn set_params_json(&mut self, v: Value) -> anyhow::Result<()> {
        self.params = serde_json::from_value(v)?;
        Ok(())
    }
    fn apply_mode(&mut self, mode: Mode) {
        self.params.apply_mode(mode);
    }
    fn run(&self, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
        (self.run)(&self.params, ctx)
    }
}

/// One `--set KEY=VALUE` override. `KEY` may be a dotted path into nested parameters
/// (`solver.max_iter`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Override {
    /// The parameter name.
    pub key: String,
    /// The value as typed.
    pub raw: String,
}

impl FromStr for Override {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.split_once('=') {
            Some((k, v)) if !k.trim().is_empty() => Ok(Self {
                key: k.trim().to_string(),
                raw: v.to_string(),
            }),
            _ => Err(format!("expected KEY=VALUE, got `{s}`")),
        }
    }
}

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}={}", self.key, self.raw)
    }
}

/// Error unless `v` is finite and > 0: `parameter `name` must be > 0, got v`.
pub fn ensure_positive(name: &str, v: f64) -> anyhow::Result<()> {
    anyhow::ensure!(
        v > 0.0 && v.is_finite(),
        "parameter `{name}` must be > 0, got {v}"
    );
    Ok(())
}

/// Error unless `v` is finite and at least `min` (in `unit`, e.g. "grain diameters"),
/// naming the parameter and its value.
pub fn ensure_at_least(name: &str, v: f64, min: f64, unit: &str) -> anyhow::Result<()> {
    anyhow::ensure!(
        v >= min && v.is_finite(),
        "parameter `{name}` must be >= {min} {unit}, got {v}"
    );
    Ok(())
}

/// The leaf keys of a parameter object, nested objects as dotted paths.
pub fn param_keys(params: &Value) -> Vec<String> {
    fn walk(prefix: &str, v: &Value, out: &mut Vec<String>) {
        if let Value::Object(map) = v {
            for (k, child) in map {
                let path = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                match child {
                    Value::Object(m) if !m.is_empty() => walk(&path, child, out),
                    _ => out.push(path),
                }
            }
        }
    }
    let mut out = Vec::new();
    walk("", params, &mut out);
    out
}

fn pointer(key: &str) -> String {
    key.split('.')
        .map(|part| format!("/{}", part.replace('~', "~0").replace('/', "~1")))
        .collect()
}

/// Applies the overrides to every case that has the key.
///
/// Errors: a key that none of `cases` has (the message lists the valid keys), a value
/// that does not parse to the type of the field (naming case, key, value and type).
pub fn apply_overrides(cases: &mut [Box<dyn Case>], overrides: &[Override]) -> anyhow::Result<()> {
    for ov in overrides {
        let ptr = pointer(&ov.key);
        let mut found = false;
        for case in cases.iter_mut() {
            let mut params = case.params_json();
            let Some(slot) = params.pointer_mut(&ptr) else {
                continue;
            };
            found = true;
            *slot = coerce(case.name(), &ov.key, slot, &ov.raw)?;
            case.set_params_json(params).with_context(|| {
                format!(
                    "{}: parameter `{}` rejects `{}`",
                    case.name(),
                    ov.key,
                    ov.raw
                )
            })?;
        }
        if !found {
            let keys: BTreeSet<String> = cases
                .iter()
                .flat_map(|c| param_keys(&c.params_json()))
                .collect();
            let list = if keys.is_empty() {
                "(none)".to_string()
            } else {
                keys.into_iter().collect::<Vec<_>>().join(", ")
            };
            bail!(
                "unknown parameter `{}`: no selected case has it; valid keys of the selected cases: {list}",
                ov.key
            );
        }
    }
    Ok(())
}

/// Parses `raw` as JSON (falling back to a JSON string) and checks it against the type
/// of the `current` value.
fn coerce(case: &str, key: &str, current: &Value, raw: &str) -> anyhow::Result<Value> {
    let parsed: Value =
        serde_json::from_str(raw).unwrap_or_else(|_| Value::String(raw.to_string()));
    let mismatch =
        |expected: &str| anyhow!("{case}: parameter `{key}` expects {expected}, got `{raw}`");
    Ok(match current {
        Value::Number(n) if n.is_f64() => match parsed {
            Value::Number(_) => parsed,
            _ => return Err(mismatch("a number")),
        },
        Value::Number(_) => {
            let as_int = match &parsed {
                Value::Number(p) if p.is_i64() || p.is_u64() => Some(parsed.clone()),
                Value::Number(p) => p
                    .as_f64()
                    .filter(|f| f.fract() == 0.0 && f.abs() < 9.0e15)
                    .map(|f| Value::from(f as i64)),
                _ => None,
            };
            // The sign (u32 against i32 fields) is left to serde, which names the type.
            as_int.ok_or_else(|| mismatch("an integer"))?
        }
        Value::Bool(_) => match parsed {
            Value::Bool(_) => parsed,
            _ => return Err(mismatch("a boolean (true or false)")),
        },
        Value::String(_) => match parsed {
            Value::String(_) => parsed,
            _ => Value::String(raw.to_string()),
        },
        Value::Array(items) => match parsed {
            Value::Array(_) => parsed,
            // One value for a list of numbers: a list of one (`--set orifice_diameter=0.02`).
            Value::Number(_) if items.iter().all(Value::is_number) => Value::Array(vec![parsed]),
            // One word for a list of strings: a list of one (`--set method=smc`).
            Value::String(_) if items.iter().all(Value::is_string) => Value::Array(vec![parsed]),
            _ => return Err(mismatch("a JSON array such as [1, 2, 3]")),
        },
        Value::Object(_) => match parsed {
            Value::Object(_) => parsed,
            _ => return Err(mismatch("a JSON object")),
        },
        // An optional field currently unset: accept any JSON, serde checks the type.
        Value::Null => parsed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::testing;

    fn ov(s: &str) -> Override {
        s.parse().unwrap()
    }

    fn err_of(cases: &mut [Box<dyn Case>], s: &str) -> String {
        format!("{:#}", apply_overrides(cases, &[ov(s)]).unwrap_err())
    }

    #[test]
    fn parse_override() {
        assert_eq!(
            ov("h=1e-3"),
            Override {
                key: "h".into(),
                raw: "1e-3".into()
            }
        );
        assert_eq!(ov("name=a=b").raw, "a=b");
        assert_eq!(ov("s=").raw, "");
        assert!("h".parse::<Override>().is_err());
        assert!("=3".parse::<Override>().is_err());
    }

    #[test]
    fn sets_values_of_each_type() {
        let mut cases = vec![testing::decay_case(), testing::failing_case()];
        let sets = [
            "h=0.02",
            "steps_hint=7",
            "label=hello",
            "flag=true",
            "t_end=2",
        ];
        let sets: Vec<Override> = sets.iter().map(|s| ov(s)).collect();
        apply_overrides(&mut cases, &sets).unwrap();
        let p = cases[0].params_json();
        assert_eq!(p["h"], 0.02);
        assert_eq!(p["steps_hint"], 7);
        assert_eq!(p["label"], "hello");
        assert_eq!(p["flag"], true);
        assert_eq!(p["t_end"], 2.0);
        // `h` exists in both cases: applied to both.
        assert_eq!(cases[1].params_json()["h"], 0.02);
        // A number-looking string stays a string; 1e2 is accepted as an integer.
        apply_overrides(&mut cases, &[ov("label=123"), ov("steps_hint=1e2")]).unwrap();
        assert_eq!(cases[0].params_json()["label"], "123");
        assert_eq!(cases[0].params_json()["steps_hint"], 100);
    }

    #[test]
    fn unknown_key_lists_valid_keys() {
        let mut cases = vec![testing::decay_case()];
        let e = err_of(&mut cases, "dt=0.1");
        assert!(e.contains("unknown parameter `dt`"), "{e}");
        assert!(e.contains("flag, h, k, label, steps_hint, t_end"), "{e}");
    }

    #[test]
    fn type_mismatch_names_case_key_value_and_type() {
        let mut cases = vec![testing::decay_case()];
        let e = err_of(&mut cases, "h=abc");
        assert_eq!(e, "test-decay: parameter `h` expects a number, got `abc`");
        let e = err_of(&mut cases, "steps_hint=1.5");
        assert_eq!(
            e,
            "test-decay: parameter `steps_hint` expects an integer, got `1.5`"
        );
        let e = err_of(&mut cases, "steps_hint=-3");
        assert!(
            e.starts_with("test-decay: parameter `steps_hint` rejects `-3`: "),
            "{e}"
        );
        let e = err_of(&mut cases, "flag=yes");
        assert!(e.contains("`flag` expects a boolean"), "{e}");
        // Nothing was changed by the failed overrides.
        assert_eq!(cases[0].params_json(), testing::decay_case().params_json());
    }

    #[test]
    fn one_number_sets_a_list_of_numbers() {
        let list = serde_json::json!([0.1, 0.2]);
        assert_eq!(
            coerce("c", "d", &list, "0.5").unwrap(),
            serde_json::json!([0.5])
        );
        assert_eq!(
            coerce("c", "d", &list, "[1, 2]").unwrap(),
            serde_json::json!([1, 2])
        );
        let names = serde_json::json!(["apgd"]);
        assert!(coerce("c", "d", &names, "3").is_err());
        assert!(coerce("c", "d", &list, "abc").is_err());
    }

    #[test]
    fn one_word_sets_a_list_of_strings() {
        let methods = serde_json::json!(["nsc", "smc"]);
        assert_eq!(
            coerce("c", "method", &methods, "smc").unwrap(),
            serde_json::json!(["smc"])
        );
        assert_eq!(
            coerce("c", "method", &methods, r#"["smc","nsc"]"#).unwrap(),
            serde_json::json!(["smc", "nsc"])
        );
        assert!(coerce("c", "method", &methods, "3").is_err());
    }

    #[test]
    fn dotted_keys_reach_nested_params() {
        let v = serde_json::json!({"a": 1, "s": {"x": 1.0, "y": [1, 2]}});
        assert_eq!(param_keys(&v), vec!["a", "s.x", "s.y"]);
        assert_eq!(pointer("s.x"), "/s/x");
    }
}
