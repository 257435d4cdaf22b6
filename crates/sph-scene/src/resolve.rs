//! From a scene file's text to the text a scene is built from: overrides by dotted path
//! (`--set material.nu=0.3`, `--set body.block.dp=1e-3`), then the `[parameters]` table,
//! whose names `${…}` in any value uses (`dp = "${H / 20}"`).
//!
//! The edits are made to the text itself, value by value, so every line of the file keeps its
//! number; each stretch of the result remembers where it came from (a byte of the file, or an
//! override), so an error names the file's line, or the `--set` that made the value.

use crate::build::SceneError;
use crate::expr;
use std::ops::Range;
use toml_edit::{Document, Item, Table, Value};

/// Top-level keys of a scene file (a parameter may not take one of these names).
pub(crate) const SCENE_KEYS: [&str; 14] = [
    "name",
    "dimension",
    "method",
    "end_time",
    "material",
    "numerics",
    "output",
    "body",
    "constraint",
    "load",
    "probe",
    "tool",
    "relaxation",
    "parameters",
];

/// One `KEY=VALUE` override.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The dotted path as written (`material.nu`, `body.block.dp`, `body[0].dp`, or a
    /// parameter's name).
    pub key: String,
    /// The value as written: a TOML value (`0.3`, `[0.0, 1.0]`, `true`, `"tl"`), or a bare
    /// word, taken as a string (`ul-enog`).
    pub value: String,
}

impl Override {
    /// Splits `KEY=VALUE`.
    ///
    /// # Errors
    /// No `=`, or an empty key.
    pub fn parse(assignment: &str) -> Result<Self, String> {
        match assignment.split_once('=') {
            Some((k, v)) if !k.trim().is_empty() => Ok(Self {
                key: k.trim().to_string(),
                value: v.trim().to_string(),
            }),
            _ => Err(format!(
                "`{assignment}`: expected KEY=VALUE (a dotted path such as material.nu=0.3, \
                 body.NAME.dp=1e-3, or a name of [parameters])"
            )),
        }
    }
}

impl std::fmt::Display for Override {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "--set {}={}", self.key, self.value)
    }
}

/// Where a stretch of the resolved text came from.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Origin {
    /// The file, from this byte on.
    File(usize),
    /// An override (index in the list).
    Override(usize),
}

/// The resolved text and where each of its stretches came from.
#[derive(Clone, Debug)]
pub(crate) struct Resolved {
    /// The file's text.
    pub original: String,
    /// The text the scene is built from.
    pub text: String,
    /// `(start in text, origin)`, in order; a stretch runs to the next start.
    segments: Vec<(usize, Origin)>,
    /// The overrides applied.
    pub overrides: Vec<Override>,
    /// The parameters, resolved, in the file's order (overridden ones included).
    pub parameters: Vec<(String, toml::Value)>,
}

impl Resolved {
    /// Where the line holding byte `offset` of the resolved text came from: the file's line
    /// (none for a line an override inserted), and the override that wrote any of it.
    pub fn origin(&self, offset: usize) -> (Option<usize>, Option<&Override>) {
        let offset = offset.min(self.text.len());
        let segment = |o: usize| {
            self.segments
                .partition_point(|s| s.0 <= o)
                .saturating_sub(1)
        };
        let line = match self.segments.get(segment(offset)) {
            Some(&(start, Origin::File(at))) => {
                let o = (at + offset - start).min(self.original.len());
                Some(line_of(&self.original, o))
            }
            Some(&(_, Origin::Override(_))) => None,
            None => Some(line_of(&self.original, offset)),
        };
        // The line's extent in the resolved text, and the overrides that wrote into it.
        let start = self.text[..offset].rfind('\n').map_or(0, |i| i + 1);
        let end = self.text[offset..]
            .find('\n')
            .map_or(self.text.len(), |i| offset + i);
        let by = (segment(start)..=segment(end)).find_map(|k| match self.segments.get(k) {
            Some(&(at, Origin::Override(i))) if at <= end => self.overrides.get(i),
            _ => None,
        });
        (line, by)
    }
}

/// 1-based line of byte `offset`.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    let mut o = offset.min(text.len());
    while !text.is_char_boundary(o) {
        o -= 1;
    }
    text[..o].matches('\n').count() + 1
}

/// An edit of the file's text: replace `range` by `text` (an empty range inserts).
struct Edit {
    range: Range<usize>,
    text: String,
    origin: Origin,
}

/// Applies `overrides` and the `[parameters]` of `original` (see the module documentation).
pub(crate) fn resolve(
    original: &str,
    file: &str,
    overrides: &[Override],
) -> Result<Resolved, SceneError> {
    let fail = |offset: Option<usize>, key: &str, message: String| {
        SceneError::new(file, offset.map(|o| line_of(original, o)), key, message)
    };
    let doc = Document::parse(original).map_err(|e| {
        let offset = e.span().map(|s| s.start);
        // `[material]` and `[[material]]` together: say which rule it breaks.
        let line = offset.map_or("", |o| {
            let start = original[..o.min(original.len())]
                .rfind('\n')
                .map_or(0, |i| i + 1);
            original[start..].lines().next().unwrap_or("")
        });
        let header = line
            .trim()
            .trim_start_matches('[')
            .trim_end_matches(']')
            .trim();
        if e.message().contains("duplicate key") && header == "material" {
            return fail(
                offset,
                "material",
                "give one [material] table (every body's) or named [[material]] tables, not both"
                    .into(),
            );
        }
        fail(offset, "scene", e.message().trim().to_string())
    })?;
    let root = doc.as_table();
    if root.contains_key("case") && !root.contains_key("body") {
        let case = root
            .get("case")
            .and_then(Item::as_str)
            .unwrap_or("CASE")
            .to_string();
        return Err(fail(
            None,
            "case",
            format!(
                "{file} is a parameter file of case `{case}` (as `sph list --toml` writes), not \
                 a scene: run it with `sph run {case} --config {file}`"
            ),
        ));
    }
    // The parameters and the overrides of them.
    let declared: Vec<(String, Value, Option<usize>)> = match root.get("parameters") {
        None => Vec::new(),
        Some(Item::Table(t)) => {
            let mut out = Vec::new();
            for (name, item) in t.iter() {
                let at = item.span().map(|s| s.start);
                let key = format!("parameters.{name}");
                if !expr::is_identifier(name) || expr::is_reserved(name) {
                    return Err(fail(
                        at,
                        &key,
                        "a parameter's name is a letter or `_` followed by letters, digits or \
                         `_`, and not a function of `${…}` or `pi`"
                            .into(),
                    ));
                }
                if SCENE_KEYS.contains(&name) {
                    return Err(fail(
                        at,
                        &key,
                        format!(
                            "`{name}` is a key of the scene itself; name the parameter otherwise"
                        ),
                    ));
                }
                match item {
                    Item::Value(v) if !v.is_inline_table() => {
                        out.push((name.to_string(), v.clone(), at))
                    }
                    _ => {
                        return Err(fail(
                            at,
                            &key,
                            "a parameter is a number, a string, a boolean or an array".into(),
                        ))
                    }
                }
            }
            out
        }
        Some(other) => {
            return Err(fail(
                other.span().map(|s| s.start),
                "parameters",
                "must be a table: [parameters] with `name = value` lines".into(),
            ))
        }
    };
    let mut param_override: Vec<Option<usize>> = vec![None; declared.len()];
    let mut path_overrides = Vec::new();
    for (k, o) in overrides.iter().enumerate() {
        let name = o.key.strip_prefix("parameters.").unwrap_or(&o.key);
        match declared.iter().position(|d| d.0 == name) {
            Some(p) => param_override[p] = Some(k),
            None if o.key.starts_with("parameters.") => {
                return Err(fail(
                    None,
                    &o.to_string(),
                    format!(
                        "no parameter `{name}`; the parameters: {}",
                        names_or_none(declared.iter().map(|d| d.0.as_str()))
                    ),
                ))
            }
            None => path_overrides.push(k),
        }
    }
    // Resolve the parameters (in any order; each may use the others).
    let mut params = Parameters {
        declared: &declared,
        overrides,
        param_override: &param_override,
        values: vec![None; declared.len()],
        busy: vec![false; declared.len()],
    };
    for p in 0..declared.len() {
        params.value(p).map_err(|(at, key, m)| fail(at, &key, m))?;
    }
    // The edits: overridden values, then `${…}` in every other string.
    let mut edits: Vec<Edit> = Vec::new();
    for &k in &path_overrides {
        let o = &overrides[k];
        let value = params
            .render_override(&o.value)
            .map_err(|m| fail(None, &o.to_string(), m))?;
        let mut name_of = |raw: &str| -> String {
            match params.render_value(raw) {
                Ok(toml::Value::String(s)) => s,
                _ => raw.to_string(),
            }
        };
        let edit = locate(original, root, o, &value, &mut name_of)
            .map_err(|m| fail(None, &o.to_string(), m))?;
        edits.push(Edit {
            origin: Origin::Override(k),
            ..edit
        });
    }
    let mut strings = Vec::new();
    collect_strings(&Item::Table(root.clone()), &mut Vec::new(), &mut strings);
    for (path, range, s) in strings {
        if path.first().map(String::as_str) == Some("parameters")
            || edits.iter().any(|e| overlaps(&e.range, &range))
        {
            continue;
        }
        let rendered = params
            .render(&s)
            .map_err(|m| fail(Some(range.start), &display_path(&path), m))?;
        edits.push(Edit {
            text: pad_lines(rendered, &original[range.clone()]),
            range: range.clone(),
            origin: Origin::File(range.start),
        });
    }
    edits.sort_by_key(|e| (e.range.start, e.range.end));
    if let Some(w) = edits
        .windows(2)
        .find(|w| overlaps(&w[0].range, &w[1].range))
    {
        return Err(fail(
            Some(w[1].range.start),
            "--set",
            "two overrides set the same value".into(),
        ));
    }
    // Apply them, recording where each stretch came from.
    let (mut text, mut segments, mut at) = (String::new(), Vec::new(), 0);
    for e in &edits {
        segments.push((text.len(), Origin::File(at)));
        text.push_str(&original[at..e.range.start]);
        segments.push((text.len(), e.origin));
        text.push_str(&e.text);
        at = e.range.end;
    }
    segments.push((text.len(), Origin::File(at)));
    text.push_str(&original[at..]);
    let parameters = declared
        .iter()
        .zip(params.values)
        .map(|(d, v)| (d.0.clone(), v.expect("resolved")))
        .collect();
    Ok(Resolved {
        original: original.into(),
        text,
        segments,
        overrides: overrides.to_vec(),
        parameters,
    })
}

/// `body`, `0`, `dp` → `body[0].dp`, as the scene's other errors name keys.
fn display_path(path: &[String]) -> String {
    let mut out = String::new();
    for p in path {
        if p.parse::<usize>().is_ok() {
            out.push_str(&format!("[{p}]"));
        } else {
            if !out.is_empty() {
                out.push('.');
            }
            out.push_str(p);
        }
    }
    out
}

fn overlaps(a: &Range<usize>, b: &Range<usize>) -> bool {
    a.start < b.end && b.start < a.end
}

fn names_or_none<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let v: Vec<&str> = names.collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

/// `text` followed by as many newlines as it lacks to cover the lines of `replaced`, so the
/// lines after it keep their numbers.
fn pad_lines(mut text: String, replaced: &str) -> String {
    let missing = replaced
        .matches('\n')
        .count()
        .saturating_sub(text.matches('\n').count());
    text.extend(std::iter::repeat_n('\n', missing));
    text
}

/// The resolved parameters.
struct Parameters<'a> {
    declared: &'a [(String, Value, Option<usize>)],
    overrides: &'a [Override],
    param_override: &'a [Option<usize>],
    values: Vec<Option<toml::Value>>,
    busy: Vec<bool>,
}

/// An error while resolving a parameter: where, which key, what.
type ParamError = (Option<usize>, String, String);

impl Parameters<'_> {
    /// The value of parameter `p`, resolving it (and those it uses) on first use.
    fn value(&mut self, p: usize) -> Result<toml::Value, ParamError> {
        if let Some(v) = &self.values[p] {
            return Ok(v.clone());
        }
        let (name, declared, at) = &self.declared[p];
        let (raw, key, at) = match self.param_override[p] {
            Some(k) => (
                parse_value(&self.overrides[k].value),
                self.overrides[k].to_string(),
                None,
            ),
            None => (to_toml(declared), format!("parameters.{name}"), *at),
        };
        if self.busy[p] {
            return Err((at, key, format!("`{name}` is defined through itself")));
        }
        self.busy[p] = true;
        let v = match &raw {
            toml::Value::String(s) if s.contains("${") => {
                self.render_value(s).map_err(|m| (at, key.clone(), m))?
            }
            _ => raw,
        };
        self.busy[p] = false;
        self.values[p] = Some(v.clone());
        Ok(v)
    }

    /// A name's value as a number, for arithmetic.
    fn number(&mut self, name: &str) -> Result<f64, String> {
        let p = self.position(name)?;
        match self.value(p).map_err(|e| e.2)? {
            toml::Value::Integer(i) => Ok(i as f64),
            toml::Value::Float(x) => Ok(x),
            other => Err(format!("`{name}` is {}, not a number", other.type_str())),
        }
    }

    fn position(&self, name: &str) -> Result<usize, String> {
        self.declared
            .iter()
            .position(|d| d.0 == name)
            .ok_or_else(|| {
                format!(
                    "unknown parameter `{name}`; the parameters: {}",
                    names_or_none(self.declared.iter().map(|d| d.0.as_str()))
                )
            })
    }

    /// The value of a string with `${…}`: the value itself when the string is one `${…}`
    /// (a parameter's value of any type, or a number), else the string with each `${…}`
    /// replaced by its text.
    fn render_value(&mut self, s: &str) -> Result<toml::Value, String> {
        let inner = s
            .strip_prefix("${")
            .and_then(|r| r.strip_suffix('}'))
            .filter(|r| !r.contains("${") && !r.contains('}'));
        if let Some(expr) = inner {
            let name = expr.trim();
            if expr::is_identifier(name) && name != "pi" {
                let p = self.position(name)?;
                return self.value(p).map_err(|e| e.2);
            }
            let x = self.evaluate(expr)?;
            return Ok(number_value(x));
        }
        let mut out = String::new();
        let mut rest = s;
        while let Some(k) = rest.find("${") {
            out.push_str(&rest[..k]);
            let end = rest[k..]
                .find('}')
                .ok_or_else(|| format!("`{s}`: a `${{` without its `}}`"))?;
            let expr = &rest[k + 2..k + end];
            let name = expr.trim();
            let piece = if expr::is_identifier(name) && name != "pi" {
                let p = self.position(name)?;
                self.value(p).map_err(|e| e.2)?
            } else {
                number_value(self.evaluate(expr)?)
            };
            out.push_str(&match piece {
                toml::Value::String(t) => t,
                toml::Value::Float(x) => format_number(x),
                other => other.to_string(),
            });
            rest = &rest[k + end + 1..];
        }
        out.push_str(rest);
        Ok(toml::Value::String(out))
    }

    fn evaluate(&mut self, expr: &str) -> Result<f64, String> {
        let x = expr::evaluate(expr, &mut |n| self.number(n))
            .map_err(|m| format!("in `${{{expr}}}`: {m}"))?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(format!("`${{{expr}}}` = {x}: not a finite number"))
        }
    }

    /// A string value of the file, rendered as TOML.
    fn render(&mut self, s: &str) -> Result<String, String> {
        Ok(render_toml(&self.render_value(s)?))
    }

    /// An override's value, `${…}` resolved, rendered as TOML.
    fn render_override(&mut self, raw: &str) -> Result<String, String> {
        let v = parse_value(raw);
        let v = match &v {
            toml::Value::String(s) if s.contains("${") => self.render_value(s)?,
            _ => v,
        };
        Ok(render_toml(&v))
    }
}

/// A number from `${…}` arithmetic: an integer when it is one (so it can fill an integer key
/// such as `dimension` or `max_steps`; a float key takes integers too).
fn number_value(x: f64) -> toml::Value {
    if x.fract() == 0.0 && x.abs() < 9.0e15 {
        toml::Value::Integer(x as i64)
    } else {
        toml::Value::Float(x)
    }
}

/// A float in text: the shortest form that reads back to it (`0.0005`, `1e-7`).
fn format_number(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 9.0e15 {
        format!("{}", x as i64)
    } else {
        format!("{x:?}")
    }
}

/// A value as TOML text.
fn render_toml(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(x) if x.is_finite() => {
            let s = format!("{x:?}");
            if s.contains('.') || s.contains('e') {
                s
            } else {
                format!("{s}.0")
            }
        }
        other => other.to_string(),
    }
}

/// An override's value: a TOML value, or else the text as a string (a bare word).
fn parse_value(raw: &str) -> toml::Value {
    match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
        Ok(mut t) if t.len() == 1 => t.remove("v").expect("one key"),
        _ => toml::Value::String(raw.to_string()),
    }
}

/// A toml_edit value as a toml value.
fn to_toml(v: &Value) -> toml::Value {
    parse_value(&v.to_string())
}

/// Every string value below `item` with its path and span.
fn collect_strings(
    item: &Item,
    path: &mut Vec<String>,
    out: &mut Vec<(Vec<String>, Range<usize>, String)>,
) {
    match item {
        Item::Table(t) => {
            for (k, i) in t.iter() {
                path.push(k.to_string());
                collect_strings(i, path, out);
                path.pop();
            }
        }
        Item::ArrayOfTables(a) => {
            for (n, t) in a.iter().enumerate() {
                path.push(n.to_string());
                for (k, i) in t.iter() {
                    path.push(k.to_string());
                    collect_strings(i, path, out);
                    path.pop();
                }
                path.pop();
            }
        }
        Item::Value(v) => collect_value_strings(v, path, out),
        Item::None => {}
    }
}

fn collect_value_strings(
    v: &Value,
    path: &mut Vec<String>,
    out: &mut Vec<(Vec<String>, Range<usize>, String)>,
) {
    match v {
        Value::String(s) if s.value().contains("${") => {
            if let Some(span) = v.span() {
                out.push((path.clone(), span, s.value().clone()));
            }
        }
        Value::Array(a) => {
            for (n, x) in a.iter().enumerate() {
                path.push(n.to_string());
                collect_value_strings(x, path, out);
                path.pop();
            }
        }
        Value::InlineTable(t) => {
            for (k, x) in t.iter() {
                path.push(k.to_string());
                collect_value_strings(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

/// Where an insertion goes: the span of the innermost table with one (a header table, an
/// inline table, or none: the top of the file), and the index of the first key below it.
type Anchor = (Option<Range<usize>>, bool, usize);

/// The edit an override makes: the span of the value it replaces, or an insertion.
fn locate(
    original: &str,
    root: &Table,
    o: &Override,
    value: &str,
    name_of: &mut dyn FnMut(&str) -> String,
) -> Result<Edit, String> {
    let segments = split_path(&o.key)?;
    if SCENE_KEYS.iter().all(|k| *k != segments[0]) {
        return Err(format!(
            "`{}` is neither a key of the scene ({}) nor a name of its [parameters]",
            segments[0],
            SCENE_KEYS[..13].join(", ")
        ));
    }
    let not_table = |k: usize, v: &Value| {
        format!(
            "`{}` is {}, not a table",
            segments[..=k].join("."),
            v.type_name()
        )
    };
    let mut table = root;
    let mut anchor: Anchor = (None, false, 0);
    let mut k = 0;
    // Header tables and lists of them.
    let inline = loop {
        let seg = &segments[k];
        let last = k + 1 == segments.len();
        match table.get(seg) {
            None | Some(Item::None) => return insertion(original, anchor, &segments, value),
            Some(Item::Value(v)) if last => return replace(v.span(), value, original),
            Some(Item::Value(Value::InlineTable(inner))) => {
                anchor = (inner.span(), true, k + 1);
                k += 1;
                break inner;
            }
            Some(Item::Value(Value::Array(a))) => {
                return in_array(a, &segments, k + 1, value, original)
            }
            Some(Item::Value(v)) => return Err(not_table(k, v)),
            Some(Item::Table(_)) if last => {
                return Err(format!(
                    "`{}` is a table: set one of its keys ({}.KEY=VALUE)",
                    o.key, o.key
                ))
            }
            Some(Item::Table(inner)) => {
                // A table without a place of its own (implicit, or of dotted keys) takes new
                // keys as dotted keys at the top of the file.
                anchor = match inner.span() {
                    Some(r) => (Some(r), false, k + 1),
                    None => (None, false, 0),
                };
                table = inner;
                k += 1;
            }
            Some(Item::ArrayOfTables(list)) => {
                let Some(which) = segments.get(k + 1) else {
                    return Err(format!(
                        "`{seg}` is a list of tables: name one and its key \
                         ({seg}.NAME.KEY=VALUE or {seg}[INDEX].KEY=VALUE)"
                    ));
                };
                let names: Vec<String> = list
                    .iter()
                    .map(|t| name_of(t.get("name").and_then(Item::as_str).unwrap_or("")))
                    .collect();
                let index = match which.parse::<usize>() {
                    Ok(i) if i < list.len() => i,
                    Ok(i) => {
                        return Err(format!(
                            "[[{seg}]] has {} entries; index {i} is beyond them",
                            list.len()
                        ))
                    }
                    Err(_) => names.iter().position(|n| n == which).ok_or_else(|| {
                        format!(
                            "no {seg} named `{which}`; the {seg} names: {}",
                            names_or_none(
                                names.iter().map(String::as_str).filter(|n| !n.is_empty())
                            )
                        )
                    })?,
                };
                if k + 2 == segments.len() {
                    return Err(format!(
                        "`{}` is a table: set one of its keys",
                        segments.join(".")
                    ));
                }
                let entry = list.get(index).expect("in range");
                anchor = (entry.span(), false, k + 2);
                table = entry;
                k += 2;
            }
        }
    };
    // Inline tables.
    let mut t = inline;
    loop {
        let last = k + 1 == segments.len();
        match t.get(&segments[k]) {
            None => return insertion(original, anchor, &segments, value),
            Some(v) if last => return replace(v.span(), value, original),
            Some(Value::InlineTable(inner)) => {
                anchor = (inner.span(), true, k + 1);
                t = inner;
                k += 1;
            }
            Some(Value::Array(a)) => return in_array(a, &segments, k + 1, value, original),
            Some(v) => return Err(not_table(k, v)),
        }
    }
}

/// `a.b[2].c` → `a`, `b`, `2`, `c`; `body[plate-1.5].dp` and `body."plate-1.5".dp` name an
/// entry whose name holds dots.
fn split_path(key: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut current = String::new();
    let mut chars = key.chars().peekable();
    let empty = || format!("`{key}`: an empty key");
    while let Some(c) = chars.next() {
        match c {
            '.' => {
                if current.is_empty() {
                    if out.is_empty() {
                        return Err(empty());
                    }
                    // After `]` or a quoted part: nothing to push.
                } else {
                    out.push(std::mem::take(&mut current));
                }
            }
            '[' => {
                if !current.is_empty() {
                    out.push(std::mem::take(&mut current));
                } else if out.is_empty() {
                    return Err(empty());
                }
                let mut inner = String::new();
                loop {
                    match chars.next() {
                        Some(']') => break,
                        Some(x) => inner.push(x),
                        None => return Err(format!("`{key}`: a `[` without `]`")),
                    }
                }
                let inner = inner.trim().trim_matches('"').to_string();
                if inner.is_empty() {
                    return Err(empty());
                }
                out.push(inner);
                if chars.peek().is_some_and(|&c| c != '.' && c != '[') {
                    return Err(format!("`{key}`: expected `.` after `]`"));
                }
            }
            '"' if current.is_empty() => {
                let mut inner = String::new();
                loop {
                    match chars.next() {
                        Some('"') => break,
                        Some(x) => inner.push(x),
                        None => return Err(format!("`{key}`: a `\"` without its pair")),
                    }
                }
                out.push(inner);
            }
            c => current.push(c),
        }
    }
    if !current.is_empty() {
        out.push(current);
    } else if key.ends_with('.') || out.is_empty() {
        return Err(empty());
    }
    Ok(out)
}

/// Replaces the value at `span`.
fn replace(span: Option<Range<usize>>, value: &str, original: &str) -> Result<Edit, String> {
    let range = span.ok_or("the value has no place in the file")?;
    Ok(Edit {
        text: pad_lines(value.to_string(), &original[range.clone()]),
        range,
        origin: Origin::File(0),
    })
}

/// An element of an inline array: `…velocity.1=2.0`.
fn in_array(
    a: &toml_edit::Array,
    segments: &[String],
    k: usize,
    value: &str,
    original: &str,
) -> Result<Edit, String> {
    let path = segments[..k].join(".");
    let Some(index) = segments.get(k) else {
        return replace(a.span(), value, original);
    };
    let i: usize = index
        .parse()
        .map_err(|_| format!("`{path}` is an array: index it by number ({path}.0)"))?;
    match a.get(i) {
        Some(v) if k + 1 == segments.len() => replace(v.span(), value, original),
        Some(_) => Err(format!("`{path}.{i}` is not a table")),
        None => Err(format!(
            "`{path}` has {} elements; index {i} is beyond them",
            a.len()
        )),
    }
}

/// Inserts `keys = value` for the keys of `segments` below the place `anchor` describes:
/// after a table's header line, before an inline table's `}`, or (with the whole path) at the
/// top of the file.
fn insertion(
    original: &str,
    anchor: Anchor,
    segments: &[String],
    value: &str,
) -> Result<Edit, String> {
    let (span, inline, from) = anchor;
    let from = if span.is_some() { from } else { 0 };
    let keys = segments[from..]
        .iter()
        .map(|s| quote_key(s))
        .collect::<Vec<_>>()
        .join(".");
    match (span, inline) {
        (Some(r), true) => {
            let body = &original[r.clone()];
            let close = body.rfind('}').ok_or("an inline table without `}`")?;
            let empty = body[1..close].trim().is_empty();
            let sep = if empty { " " } else { ", " };
            let at = r.start + close;
            Ok(Edit {
                range: at..at,
                text: format!("{sep}{keys} = {value} "),
                origin: Origin::File(0),
            })
        }
        (Some(r), false) => {
            // After the header line.
            let end = original[r.end..]
                .find('\n')
                .map_or(original.len(), |i| r.end + i + 1);
            let text = if end == original.len() && !original.ends_with('\n') {
                format!("\n{keys} = {value}")
            } else {
                format!("{keys} = {value}\n")
            };
            Ok(Edit {
                range: end..end,
                text,
                origin: Origin::File(0),
            })
        }
        (None, _) => Ok(Edit {
            range: 0..0,
            text: format!("{keys} = {value}\n"),
            origin: Origin::File(0),
        }),
    }
}

fn quote_key(k: &str) -> String {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        k.to_string()
    } else {
        format!("{:?}", k)
    }
}
