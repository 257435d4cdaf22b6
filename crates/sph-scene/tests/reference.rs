//! Issue 42: docs/user-guide.md's scene-key reference is generated from the scene's
//! specification and cannot drift. The keys the scene's types accept are traced through their
//! `Deserialize` implementations (a deserializer that records every field it is asked for);
//! they, with the `[numerics]` keys of every method, must be exactly the keys the reference
//! documents; and the guide must hold the current rendering of the reference and of the
//! results' conventions. `SPH_UPDATE_DOCS=1 cargo test -p sph-scene --test reference`
//! rewrites the guide's generated sections.

use serde::de::{self, DeserializeSeed, Deserializer, IntoDeserializer, MapAccess, Visitor};
use serde::Deserialize;
use sph_scene::reference::{conventions_markdown, keys, reference_markdown};
use sph_scene::spec::{AmplitudeSpec, SceneSpec, ShapeSpec, ToolShapeSpec};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::path::PathBuf;

/// The keys seen, and the paths found to be tables (not keys themselves).
#[derive(Default)]
struct Record {
    keys: BTreeSet<String>,
    tables: BTreeSet<String>,
    /// The variants of the enum traced at the root, once known.
    variants: Option<&'static [&'static str]>,
}

#[derive(Debug)]
struct Stop(String);

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Stop {}

impl de::Error for Stop {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        Stop(msg.to_string())
    }
}

/// A deserializer that produces a value of any type while recording the keys it is asked for.
/// Enums below the root are keys of their own (a shape, an amplitude): not descended into.
#[derive(Clone, Copy)]
struct Trace<'a> {
    path: &'a str,
    record: &'a RefCell<Record>,
    /// Inside an enum that is documented on its own: record nothing.
    mute: bool,
    /// At the root of an enum's trace: the variant to take.
    variant: Option<usize>,
}

impl<'a> Trace<'a> {
    fn at(&self, path: &'a str) -> Self {
        Trace {
            path,
            variant: None,
            ..*self
        }
    }

    /// Records this path as a key (not the elements of an array: `min[]`).
    fn key(&self) {
        if !self.mute && !self.path.is_empty() && !self.path.ends_with("[]") {
            self.record.borrow_mut().keys.insert(self.path.to_string());
        }
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

const SPANNED: &str = "$__serde_spanned_private_Spanned";

macro_rules! primitive {
    ($($name:ident => $visit:ident($($value:expr)?)),* $(,)?) => {
        $(fn $name<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Stop> {
            self.key();
            v.$visit($($value)?)
        })*
    };
}

impl<'de> Deserializer<'de> for Trace<'_> {
    type Error = Stop;

    primitive! {
        deserialize_bool => visit_bool(false),
        deserialize_i8 => visit_i8(0),
        deserialize_i16 => visit_i16(0),
        deserialize_i32 => visit_i32(0),
        deserialize_i64 => visit_i64(0),
        deserialize_u8 => visit_u8(0),
        deserialize_u16 => visit_u16(0),
        deserialize_u32 => visit_u32(0),
        deserialize_u64 => visit_u64(0),
        deserialize_f32 => visit_f32(0.0),
        deserialize_f64 => visit_f64(0.0),
        deserialize_char => visit_char('x'),
        deserialize_str => visit_str(""),
        deserialize_string => visit_string(String::new()),
        deserialize_unit => visit_unit(),
        deserialize_ignored_any => visit_unit(),
        deserialize_bytes => visit_bytes(&[]),
        deserialize_byte_buf => visit_byte_buf(Vec::new()),
        deserialize_identifier => visit_str(""),
    }

    /// Only `[material]`/`[[material]]` asks for any type: traced as the list (its entries'
    /// keys at `material[]`, which the reference documents as `material.`).
    fn deserialize_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Stop> {
        self.deserialize_seq(v)
    }

    fn deserialize_option<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Stop> {
        v.visit_some(self)
    }

    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        v: V,
    ) -> Result<V::Value, Stop> {
        self.deserialize_unit(v)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        v: V,
    ) -> Result<V::Value, Stop> {
        v.visit_newtype_struct(self)
    }

    fn deserialize_seq<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Stop> {
        self.key();
        let element = format!("{}[]", self.path);
        v.visit_seq(One {
            trace: Some(Trace {
                path: Box::leak(element.into_boxed_str()),
                variant: None,
                ..self
            }),
        })
    }

    fn deserialize_tuple<V: Visitor<'de>>(self, _: usize, v: V) -> Result<V::Value, Stop> {
        self.deserialize_seq(v)
    }

    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        _: usize,
        v: V,
    ) -> Result<V::Value, Stop> {
        self.deserialize_seq(v)
    }

    fn deserialize_map<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Stop> {
        // A free-form table (`[numerics]`, `[parameters]`): a key whose entries are checked
        // elsewhere.
        self.key();
        v.visit_map(Fields {
            trace: self,
            fields: &[],
            next: 0,
        })
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, Stop> {
        if name == SPANNED {
            return v.visit_map(SpannedMap {
                trace: self,
                next: 0,
            });
        }
        if !self.mute {
            // A table: its fields are the keys, not the table.
            let mut r = self.record.borrow_mut();
            r.tables.insert(self.path.to_string());
            r.tables
                .insert(self.path.trim_end_matches("[]").to_string());
        }
        v.visit_map(Fields {
            trace: self,
            fields,
            next: 0,
        })
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _: &'static str,
        variants: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, Stop> {
        let variant = match self.variant {
            Some(k) => {
                self.record.borrow_mut().variants = Some(variants);
                k
            }
            None => {
                // An enum below the root: one key (documented on its own), not descended into.
                self.key();
                return v.visit_enum(Variant {
                    trace: Trace { mute: true, ..self },
                    name: variants[0],
                });
            }
        };
        v.visit_enum(Variant {
            trace: self,
            name: variants[variant],
        })
    }
}

/// One element of a sequence.
struct One<'a> {
    trace: Option<Trace<'a>>,
}

impl<'de> de::SeqAccess<'de> for One<'_> {
    type Error = Stop;
    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, Stop> {
        match self.trace.take() {
            Some(t) => seed.deserialize(t).map(Some),
            None => Ok(None),
        }
    }
}

/// The fields of a struct, each traced at its path.
struct Fields<'a> {
    trace: Trace<'a>,
    fields: &'static [&'static str],
    next: usize,
}

impl<'de> MapAccess<'de> for Fields<'_> {
    type Error = Stop;
    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Stop> {
        match self.fields.get(self.next) {
            Some(f) => seed
                .deserialize(de::value::BorrowedStrDeserializer::new(f))
                .map(Some),
            None => Ok(None),
        }
    }
    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, Stop> {
        let field = self.fields[self.next];
        self.next += 1;
        let path = Box::leak(join(self.trace.path, field).into_boxed_str());
        seed.deserialize(self.trace.at(path))
    }
}

/// toml's `Spanned<T>`: a start, an end, and the value at the same path.
struct SpannedMap<'a> {
    trace: Trace<'a>,
    next: usize,
}

const SPANNED_FIELDS: [&str; 3] = [
    "$__serde_spanned_private_start",
    "$__serde_spanned_private_end",
    "$__serde_spanned_private_value",
];

impl<'de> MapAccess<'de> for SpannedMap<'_> {
    type Error = Stop;
    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Stop> {
        match SPANNED_FIELDS.get(self.next) {
            Some(f) => seed
                .deserialize(de::value::BorrowedStrDeserializer::new(f))
                .map(Some),
            None => Ok(None),
        }
    }
    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, Stop> {
        self.next += 1;
        if self.next < 3 {
            seed.deserialize(0u64.into_deserializer())
        } else {
            seed.deserialize(self.trace)
        }
    }
}

/// The chosen variant of an enum.
struct Variant<'a> {
    trace: Trace<'a>,
    name: &'static str,
}

impl<'de, 'a> de::EnumAccess<'de> for Variant<'a> {
    type Error = Stop;
    type Variant = Self;
    fn variant_seed<S: DeserializeSeed<'de>>(self, seed: S) -> Result<(S::Value, Self), Stop> {
        let v = seed.deserialize(self.name.into_deserializer())?;
        Ok((v, self))
    }
}

impl<'de> de::VariantAccess<'de> for Variant<'_> {
    type Error = Stop;
    fn unit_variant(self) -> Result<(), Stop> {
        let path = join(self.trace.path, self.name);
        self.trace.at(Box::leak(path.into_boxed_str())).key();
        Ok(())
    }
    fn newtype_variant_seed<S: DeserializeSeed<'de>>(self, seed: S) -> Result<S::Value, Stop> {
        // `union = [..]`, `table = [..]`: the variant is the key.
        let path = Box::leak(join(self.trace.path, self.name).into_boxed_str());
        let t = self.trace.at(path);
        t.key();
        seed.deserialize(Trace { mute: true, ..t })
    }
    fn tuple_variant<V: Visitor<'de>>(self, _: usize, v: V) -> Result<V::Value, Stop> {
        let path = Box::leak(join(self.trace.path, self.name).into_boxed_str());
        self.trace.at(path).deserialize_seq(v)
    }
    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, Stop> {
        let path = Box::leak(join(self.trace.path, self.name).into_boxed_str());
        v.visit_map(Fields {
            trace: self.trace.at(path),
            fields,
            next: 0,
        })
    }
}

/// The keys `T` accepts, traced at `path`.
fn trace<'de, T: Deserialize<'de>>(path: &'static str) -> BTreeSet<String> {
    let record = RefCell::new(Record::default());
    T::deserialize(Trace {
        path,
        record: &record,
        mute: false,
        variant: None,
    })
    .unwrap_or_else(|e| panic!("tracing {path}: {e}"));
    let r = record.into_inner();
    r.keys.difference(&r.tables).cloned().collect()
}

/// The keys of every variant of the enum `T`, traced at `path`.
fn trace_enum<'de, T: Deserialize<'de>>(path: &'static str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut k = 0;
    loop {
        let record = RefCell::new(Record::default());
        T::deserialize(Trace {
            path,
            record: &record,
            mute: false,
            variant: Some(k),
        })
        .unwrap_or_else(|e| panic!("tracing {path} variant {k}: {e}"));
        let r = record.into_inner();
        out.extend(r.keys.difference(&r.tables).cloned());
        k += 1;
        if k >= r.variants.map_or(0, <[_]>::len) {
            return out;
        }
    }
}

#[test]
fn the_reference_documents_exactly_the_keys_a_scene_accepts() {
    // The keys of a `[[material]]` entry are those of `[material]`.
    let mut accepted: BTreeSet<String> = trace::<SceneSpec>("")
        .into_iter()
        .map(|k| k.replace("material[].", "material."))
        .collect();
    accepted.extend(trace_enum::<ShapeSpec>("shape"));
    accepted.extend(trace_enum::<ToolShapeSpec>("tool-shape"));
    accepted.extend(trace_enum::<AmplitudeSpec>("amplitude"));
    // The free-form tables: their keys are the methods' numerics and the file's parameters.
    assert!(accepted.remove("numerics") && accepted.remove("parameters"));
    for &method in sph_scene::METHODS {
        for key in sph_scene::numerics_keys(method).unwrap() {
            accepted.insert(format!("numerics.{key}"));
        }
    }
    accepted.insert("parameters.NAME".into());
    let documented: BTreeSet<String> = keys().into_iter().map(|k| k.key).collect();
    let missing: Vec<&String> = accepted.difference(&documented).collect();
    let extra: Vec<&String> = documented.difference(&accepted).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "keys a scene accepts but the reference lacks: {missing:?}; keys the reference \
         documents but no scene accepts: {extra:?}"
    );
    assert!(documented.len() > 100, "{}", documented.len());
}

#[test]
fn every_numerics_key_names_the_methods_that_take_it() {
    let docs = keys();
    for &method in sph_scene::METHODS {
        let family = match &method[..2] {
            "tl" => "TL",
            "ul" => "UL",
            _ => "MPS",
        };
        for key in sph_scene::numerics_keys(method).unwrap() {
            let doc = docs
                .iter()
                .find(|d| d.key == format!("numerics.{key}"))
                .unwrap();
            let named = doc.methods.split(", ").any(|m| m == family || m == method);
            assert!(named, "numerics.{key}: `{}` omits {method}", doc.methods);
        }
    }
}

fn guide() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/user-guide.md")
}

/// `text` with the part between the markers of `section` replaced by `body`.
fn with_section(text: &str, section: &str, body: &str) -> String {
    let begin = format!("<!-- {section}:begin -->\n");
    let end = format!("<!-- {section}:end -->");
    let a = text
        .find(&begin)
        .unwrap_or_else(|| panic!("docs/user-guide.md has no {begin}"))
        + begin.len();
    let b = text[a..]
        .find(&end)
        .unwrap_or_else(|| panic!("docs/user-guide.md has no {end}"))
        + a;
    format!("{}{body}{}", &text[..a], &text[b..])
}

#[test]
fn the_user_guide_holds_the_current_reference() {
    let path = guide();
    let text = std::fs::read_to_string(&path).unwrap();
    let current = with_section(&text, "scene-reference", &reference_markdown());
    let current = with_section(&current, "output-conventions", &conventions_markdown());
    if std::env::var_os("SPH_UPDATE_DOCS").is_some() {
        std::fs::write(&path, &current).unwrap();
        return;
    }
    assert!(
        text == current,
        "docs/user-guide.md's scene reference or output conventions are out of date; \
         regenerate them with `SPH_UPDATE_DOCS=1 cargo test -p sph-scene --test reference`"
    );
}

/// The complete scenes the guide shows (its TOML blocks with a `dimension`) build: parsed,
/// checked and estimated (a dry run), so the examples a user copies work.
#[test]
fn the_guides_scene_examples_build() {
    let text = std::fs::read_to_string(guide()).unwrap();
    let mut built = 0;
    for block in text.split("```toml\n").skip(1) {
        let toml = &block[..block.find("```").unwrap()];
        if !toml.contains("dimension =") {
            continue;
        }
        let scene = sph_scene::Scene::parse(toml, "guide.toml", std::path::Path::new("."), "guide")
            .unwrap_or_else(|e| panic!("{e}\n{toml}"));
        let options = sph_driver::RunOptions {
            dry_run: true,
            ..Default::default()
        };
        scene
            .run(&options)
            .unwrap_or_else(|e| panic!("{e}\n{toml}"));
        built += 1;
    }
    assert!(built >= 1, "no complete scene in the guide");
}
