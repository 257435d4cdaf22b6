//! Case parameters: typed defaults taken from the papers, each with an allowed range, changed
//! from the command line (`--set key=value`) or a TOML case file.

use crate::error::CaseError;
use serde_json::{Map, Value as Json};
use sph_core::error::Num;
use std::collections::BTreeMap;

/// A parameter value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A real number.
    Float(f64),
    /// An integer.
    Int(i64),
    /// A switch.
    Bool(bool),
    /// A word from a fixed set.
    Text(String),
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Float(x) => write!(f, "{x}"),
            Value::Int(x) => write!(f, "{x}"),
            Value::Bool(x) => write!(f, "{x}"),
            Value::Text(x) => write!(f, "{x}"),
        }
    }
}

/// The allowed values of a parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// `> 0` (and finite).
    Positive,
    /// `≥ 0` (and finite).
    NonNegative,
    /// `lo < x < hi`.
    Open(f64, f64),
    /// `lo ≤ x ≤ hi`.
    Closed(f64, f64),
    /// One of these words.
    Choice(&'static [&'static str]),
    /// Anything of the right type.
    Any,
}

impl Range {
    /// The allowed values in words (`allowed range is 0 < nu < 0.5`).
    pub fn describe(&self, key: &str) -> String {
        match self {
            Range::Positive => format!("allowed range is {key} > 0"),
            Range::NonNegative => format!("allowed range is {key} >= 0"),
            Range::Open(lo, hi) => format!("allowed range is {} < {key} < {}", Num(*lo), Num(*hi)),
            Range::Closed(lo, hi) => {
                format!("allowed range is {} <= {key} <= {}", Num(*lo), Num(*hi))
            }
            Range::Choice(c) => format!("allowed values are {}", c.join(", ")),
            Range::Any => "any value of the parameter's type".into(),
        }
    }

    fn admits(&self, v: &Value) -> bool {
        let x = match v {
            Value::Float(x) => *x,
            Value::Int(i) => *i as f64,
            Value::Bool(_) => return true,
            Value::Text(t) => {
                return match self {
                    Range::Choice(c) => c.contains(&t.as_str()),
                    _ => true,
                }
            }
        };
        x.is_finite()
            && match *self {
                Range::Positive => x > 0.0,
                Range::NonNegative => x >= 0.0,
                Range::Open(lo, hi) => x > lo && x < hi,
                Range::Closed(lo, hi) => x >= lo && x <= hi,
                Range::Choice(_) | Range::Any => true,
            }
    }
}

/// One parameter of a case.
#[derive(Clone, Debug)]
pub struct Param {
    /// Key as the user writes it.
    pub key: &'static str,
    /// Default (from the paper).
    pub default: Value,
    /// Allowed values.
    pub range: Range,
    /// What it means, with units.
    pub help: &'static str,
    /// The methods the key is for (`None`: every method of the case). Setting it for another
    /// method is an error: the run could not honour it.
    pub methods: Option<&'static [&'static str]>,
}

impl Param {
    /// The key applies to `methods` only.
    pub fn only(mut self, methods: &'static [&'static str]) -> Self {
        self.methods = Some(methods);
        self
    }

    /// Whether the key applies to `method`.
    pub fn applies_to(&self, method: &str) -> bool {
        self.methods.is_none_or(|m| m.contains(&method))
    }

    /// A real parameter.
    pub fn float(key: &'static str, default: f64, range: Range, help: &'static str) -> Self {
        Self {
            key,
            default: Value::Float(default),
            range,
            help,
            methods: None,
        }
    }
    /// An integer parameter.
    pub fn int(key: &'static str, default: i64, range: Range, help: &'static str) -> Self {
        Self {
            key,
            default: Value::Int(default),
            range,
            help,
            methods: None,
        }
    }
    /// A switch.
    pub fn bool(key: &'static str, default: bool, help: &'static str) -> Self {
        Self {
            key,
            default: Value::Bool(default),
            range: Range::Any,
            help,
            methods: None,
        }
    }
    /// A word from a fixed set.
    pub fn choice(
        key: &'static str,
        default: &'static str,
        choices: &'static [&'static str],
        help: &'static str,
    ) -> Self {
        Self {
            key,
            default: Value::Text(default.into()),
            range: Range::Choice(choices),
            help,
            methods: None,
        }
    }
}

/// The parameters of one run: the case's specification and the current values.
#[derive(Clone, Debug)]
pub struct Params {
    case: String,
    specs: Vec<Param>,
    values: BTreeMap<&'static str, Value>,
    /// The keys the user set (`--set`, a parameter file), in the order set.
    given: Vec<&'static str>,
}

/// Densities and elastic moduli every case accepts: the bounds the materials themselves check
/// (`sph_materials::ElasticConstants`), so cases and scene files refuse the same values.
pub use sph_materials::{DENSITY_RANGE, MODULUS_RANGE};

/// The physical bounds of a key, by name: `density`, and the elastic moduli (`*_modulus`,
/// `lambda`, `c1`, `c2`). [`Params::new`] narrows a case's `Positive`/`NonNegative` range of
/// such a key to these bounds, so every case, also one added later, rejects a physically
/// absurd value naming the key and the range.
pub fn physical_range(key: &str, declared: Range) -> Range {
    let bounds = match key {
        "density" => DENSITY_RANGE,
        k if k.ends_with("_modulus") || matches!(k, "lambda" | "c1" | "c2") => MODULUS_RANGE,
        _ => return declared,
    };
    match declared {
        Range::Positive => Range::Closed(bounds.0, bounds.1),
        Range::NonNegative => Range::Closed(0.0, bounds.1),
        other => other,
    }
}

impl Params {
    /// Defaults of a case's parameters. Densities and moduli get their physical bounds
    /// ([`physical_range`]).
    pub fn new(case: &str, mut specs: Vec<Param>) -> Self {
        for p in &mut specs {
            p.range = physical_range(p.key, p.range);
        }
        let values = specs.iter().map(|p| (p.key, p.default.clone())).collect();
        Self {
            case: case.into(),
            specs,
            values,
            given: Vec::new(),
        }
    }

    /// Every key set explicitly applies to `method` (see [`Param::methods`]): a key of another
    /// method (`zeta` of tl-hf with `--method tl`, an updated-Lagrangian key on a TL run) is
    /// refused, never silently ignored.
    ///
    /// # Errors
    /// [`CaseError::Config`] naming the first such key and the methods it is for.
    pub fn check_method(&self, method: &str) -> Result<(), CaseError> {
        for key in &self.given {
            let spec = self.spec(key)?;
            if let Some(methods) = spec.methods.filter(|_| !spec.applies_to(method)) {
                return Err(CaseError::Config(format!(
                    "{key} is a key of {}, not of {method}: drop it or choose one of those methods",
                    methods.join(", ")
                )));
            }
        }
        Ok(())
    }

    /// The specifications (for `sph list --verbose` and the docs).
    pub fn specs(&self) -> &[Param] {
        &self.specs
    }

    fn spec(&self, key: &str) -> Result<&Param, CaseError> {
        self.specs
            .iter()
            .find(|p| p.key == key)
            .ok_or_else(|| CaseError::UnknownKey {
                case: self.case.clone(),
                key: key.into(),
                known: self
                    .specs
                    .iter()
                    .map(|p| p.key)
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// Sets `key` from its textual form (`--set key=value`), parsed by the default's type.
    pub fn set_text(&mut self, key: &str, text: &str) -> Result<(), CaseError> {
        let spec = self.spec(key)?.clone();
        let bad = |allowed: String| CaseError::InvalidValue {
            key: key.into(),
            value: text.into(),
            allowed,
        };
        let value = match spec.default {
            Value::Float(_) => Value::Float(
                text.trim()
                    .parse::<f64>()
                    .map_err(|_| bad(format!("a number; {}", spec.range.describe(key))))?,
            ),
            Value::Int(_) => Value::Int(
                text.trim()
                    .parse::<i64>()
                    .map_err(|_| bad(format!("an integer; {}", spec.range.describe(key))))?,
            ),
            Value::Bool(_) => Value::Bool(match text.trim() {
                "true" | "on" | "yes" | "1" => true,
                "false" | "off" | "no" | "0" => false,
                _ => return Err(bad("true or false".into())),
            }),
            Value::Text(_) => Value::Text(text.trim().to_string()),
        };
        self.set(key, value, text)
    }

    fn set(&mut self, key: &str, value: Value, shown: &str) -> Result<(), CaseError> {
        let spec = self.spec(key)?;
        if !spec.range.admits(&value) {
            return Err(CaseError::InvalidValue {
                key: key.into(),
                value: shown.into(),
                allowed: spec.range.describe(key),
            });
        }
        let k = spec.key;
        self.values.insert(k, value);
        Ok(())
    }

    /// Records that the user set `key` (`--set`, a parameter file), for [`Params::check_method`].
    fn mark_given(&mut self, key: &str) {
        if let Ok(spec) = self.spec(key) {
            let k = spec.key;
            if !self.given.contains(&k) {
                self.given.push(k);
            }
        }
    }

    /// Applies a `key=value` argument.
    pub fn apply_assignment(&mut self, arg: &str) -> Result<(), CaseError> {
        let (k, v) = arg
            .split_once('=')
            .ok_or_else(|| CaseError::Config(format!("--set expects key=value, got `{arg}`")))?;
        self.set_text(k.trim(), v)?;
        self.mark_given(k.trim());
        Ok(())
    }

    /// Applies a TOML case file: top-level `key = value` pairs (an optional `[params]` table is
    /// also accepted; `case` and `method` keys are returned for the caller to check).
    pub fn apply_toml(&mut self, text: &str, origin: &str) -> Result<TomlExtras, CaseError> {
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            let line = e
                .span()
                .map(|s| {
                    format!(
                        ":{}",
                        text[..s.start.min(text.len())].matches('\n').count() + 1
                    )
                })
                .unwrap_or_default();
            CaseError::Config(format!(
                "{origin}{line}: malformed TOML: {}",
                e.message().trim()
            ))
        })?;
        let mut extras = TomlExtras::default();
        let mut entries: Vec<(String, toml::Value)> = Vec::new();
        for (k, v) in table {
            match (k.as_str(), v) {
                ("case", toml::Value::String(s)) => extras.case = Some(s),
                ("method", toml::Value::String(s)) => extras.method = Some(s),
                ("params", toml::Value::Table(t)) => entries.extend(t),
                (_, v) => entries.push((k, v)),
            }
        }
        // A key's line in the file, for the error message.
        let at = |key: &str| -> String {
            text.lines()
                .position(|l| {
                    l.trim_start()
                        .strip_prefix(key)
                        .is_some_and(|r| r.trim_start().starts_with('='))
                })
                .map(|k| format!("{origin}:{}: ", k + 1))
                .unwrap_or_else(|| format!("{origin}: "))
        };
        for (k, v) in entries {
            let spec = match self.spec(&k) {
                Ok(s) => s.clone(),
                Err(e) => return Err(CaseError::Config(format!("{}{e}", at(&k)))),
            };
            let shown = v.to_string();
            let value = match (&spec.default, v) {
                (Value::Float(_), toml::Value::Float(x)) => Value::Float(x),
                (Value::Float(_), toml::Value::Integer(i)) => Value::Float(i as f64),
                (Value::Int(_), toml::Value::Integer(i)) => Value::Int(i),
                (Value::Bool(_), toml::Value::Boolean(b)) => Value::Bool(b),
                (Value::Text(_), toml::Value::String(s)) => Value::Text(s),
                (d, _) => {
                    return Err(CaseError::InvalidValue {
                        key: format!("{}{k}", at(&k)),
                        value: shown,
                        allowed: format!("a value of the same type as the default {d}"),
                    })
                }
            };
            if let Err(e) = self.set(&k, value, &shown) {
                return Err(CaseError::Config(format!("{}{e}", at(&k))));
            }
            self.mark_given(&k);
        }
        Ok(extras)
    }

    /// The current value of `key` (the case's default until something sets it), if the key
    /// exists.
    pub fn value(&self, key: &str) -> Option<&Value> {
        self.values.get(key)
    }

    /// A real parameter (integers are widened).
    pub fn f64(&self, key: &str) -> f64 {
        match &self.values[key] {
            Value::Float(x) => *x,
            Value::Int(i) => *i as f64,
            v => panic!("parameter {key} is {v}, not a number"),
        }
    }

    /// An integer parameter.
    pub fn int(&self, key: &str) -> i64 {
        match &self.values[key] {
            Value::Int(i) => *i,
            v => panic!("parameter {key} is {v}, not an integer"),
        }
    }

    /// A switch.
    pub fn flag(&self, key: &str) -> bool {
        match &self.values[key] {
            Value::Bool(b) => *b,
            v => panic!("parameter {key} is {v}, not a switch"),
        }
    }

    /// A word.
    pub fn text(&self, key: &str) -> &str {
        match &self.values[key] {
            Value::Text(s) => s,
            v => panic!("parameter {key} is {v}, not a word"),
        }
    }

    /// All values as JSON (for `/meta` and the summary).
    pub fn to_json(&self) -> Map<String, Json> {
        self.values
            .iter()
            .map(|(k, v)| {
                let j = match v {
                    Value::Float(x) => Json::from(*x),
                    Value::Int(i) => Json::from(*i),
                    Value::Bool(b) => Json::from(*b),
                    Value::Text(s) => Json::from(s.clone()),
                };
                (k.to_string(), j)
            })
            .collect()
    }
}

/// The `case` and `method` a TOML case file may name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TomlExtras {
    /// `case = "..."`.
    pub case: Option<String>,
    /// `method = "..."`.
    pub method: Option<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> Params {
        Params::new(
            "demo",
            vec![
                Param::float("nu", 0.3, Range::Open(-1.0, 0.5), "Poisson ratio"),
                Param::int("resolution", 10, Range::Closed(2.0, 400.0), "H/dp"),
                Param::bool("damping", true, "damping"),
                Param::choice("stepping", "dual", &["dual", "single"], "stepping"),
            ],
        )
    }

    #[test]
    fn set_parses_by_type_and_checks_the_range() {
        let mut p = params();
        p.apply_assignment("nu=0.45").unwrap();
        assert_eq!(p.f64("nu"), 0.45);
        p.apply_assignment("resolution = 20").unwrap();
        assert_eq!(p.int("resolution"), 20);
        p.apply_assignment("damping=off").unwrap();
        assert!(!p.flag("damping"));
        let e = p.apply_assignment("nu=0.5").unwrap_err().to_string();
        assert!(e.contains("nu") && e.contains("0.5"), "{e}");
        let e = p
            .apply_assignment("resolution=2.5")
            .unwrap_err()
            .to_string();
        assert!(e.contains("integer"), "{e}");
        let e = p
            .apply_assignment("stepping=triple")
            .unwrap_err()
            .to_string();
        assert!(e.contains("dual, single"), "{e}");
        let e = p.apply_assignment("poisson=0.3").unwrap_err().to_string();
        assert!(
            e.contains("no parameter `poisson`") && e.contains("nu"),
            "{e}"
        );
        assert!(p.apply_assignment("nu").is_err());
    }

    /// Issue 14, item 7: `density = 1e300` and `youngs_modulus = 1e-300` were accepted. Every
    /// case's density and moduli are bounded (also cases added later: the bound is by name),
    /// and every default lies inside.
    #[test]
    fn densities_and_moduli_of_every_case_have_physical_bounds() {
        let mut seen = 0;
        for case in crate::all_cases() {
            for m in case.info().methods {
                let p = case.params_for(m);
                for spec in p.specs() {
                    let physical = spec.key == "density"
                        || spec.key.ends_with("_modulus")
                        || matches!(spec.key, "lambda" | "c1" | "c2");
                    if !physical {
                        continue;
                    }
                    seen += 1;
                    let Range::Closed(lo, hi) = spec.range else {
                        panic!("{} {}: {:?}", case.info().name, spec.key, spec.range);
                    };
                    assert!(hi <= MODULUS_RANGE.1 && lo >= 0.0);
                    assert!(spec.range.admits(p.value(spec.key).unwrap()));
                    let mut q = p.clone();
                    // c2 may be 0 (Mooney–Rivlin without its second term); the rest may not.
                    let tiny = (lo > 0.0).then_some("1e-300");
                    for bad in ["1e300", "-1"].into_iter().chain(tiny) {
                        let e = q.set_text(spec.key, bad).unwrap_err().to_string();
                        assert!(e.contains(spec.key) && e.contains("<="), "{e}");
                    }
                }
            }
        }
        assert!(seen >= 20, "{seen} density/modulus keys");
    }

    #[test]
    fn toml_files_set_values_and_report_errors() {
        let mut p = params();
        let extras = p
            .apply_toml(
                "case = \"demo\"\nnu = 0.2\n[params]\nresolution = 30\n",
                "f.toml",
            )
            .unwrap();
        assert_eq!(extras.case.as_deref(), Some("demo"));
        assert_eq!((p.f64("nu"), p.int("resolution")), (0.2, 30));
        let e = p
            .apply_toml("nu = = 1", "bad.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("bad.toml") && e.contains("malformed"), "{e}");
        let e = p
            .apply_toml("nu = \"x\"", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("nu"), "{e}");
    }
}
