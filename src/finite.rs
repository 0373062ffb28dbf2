//! One guard over every report: before a report is printed or written, each of its numbers is
//! visited (through its `Serialize`) and the first that is not finite is named by its path
//! (`zones[2].change_pct = NaN`). JSON would write it as `null` and a table as `NaN`, so a
//! silent wrong number never leaves texopt.
//!
//! Two kinds of non-finite numbers are answers, not faults, and say so where they are declared:
//! - [`unbounded`]: +∞ is the answer (the least Λ of a cycle without contact); NaN is not.
//! - [`absent`] / [`absent_each`]: NaN stands for "no value" (a ratio whose run failed);
//!   JSON writes it as `null`.
//!
//! The markers are newtype wrappers by name: serde_json writes a newtype as its content, so
//! marking a field changes no file.

use serde::ser::{self, Serialize, Serializer};

const UNBOUNDED: &str = "texopt::finite::Unbounded";
const ABSENT: &str = "texopt::finite::Absent";

/// `#[serde(serialize_with = "crate::finite::unbounded")]`: +∞ is an answer here.
pub fn unbounded<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_newtype_struct(UNBOUNDED, x)
}

/// `#[serde(serialize_with = "crate::finite::absent")]`: NaN means "no value" here.
pub fn absent<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_newtype_struct(ABSENT, x)
}

/// The same for each number of a list.
pub fn absent_each<S: Serializer>(xs: &[f64], s: S) -> Result<S::Ok, S::Error> {
    use ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(xs.len()))?;
    for x in xs {
        seq.serialize_element(&Absent(*x))?;
    }
    seq.end()
}

struct Absent(f64);

impl Serialize for Absent {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        absent(&self.0, s)
    }
}

/// A number of a report that is not finite, and where it is.
#[derive(Clone, Debug, PartialEq)]
pub struct NonFinite {
    pub path: String,
    pub value: f64,
}

impl std::fmt::Display for NonFinite {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} = {}", self.path, self.value)
    }
}

/// The guard: every number of `report` finite, or marked as an answer where it is not; the
/// error names the first other one.
pub fn check<T: Serialize + ?Sized>(report: &T) -> Result<(), NonFinite> {
    match first_non_finite(report) {
        None => Ok(()),
        Some(n) => Err(n),
    }
}

impl std::error::Error for NonFinite {}

/// The first number of `report` that is not finite (and not marked as an answer), if any.
pub fn first_non_finite<T: Serialize + ?Sized>(report: &T) -> Option<NonFinite> {
    let mut path = Vec::new();
    match report.serialize(Check {
        path: &mut path,
        allow: Allow::Finite,
    }) {
        Ok(()) => None,
        Err(Found(found)) => found,
    }
}

/// Which non-finite number the current value may be.
#[derive(Clone, Copy, PartialEq)]
enum Allow {
    Finite,
    PlusInfinity,
    NaN,
}

/// The walk's error: the number found, or a `Serialize` impl's own failure (nothing to name).
#[derive(Debug)]
struct Found(Option<NonFinite>);

impl std::fmt::Display for Found {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0 {
            Some(n) => write!(f, "{n}"),
            None => write!(f, "not serialisable"),
        }
    }
}

impl std::error::Error for Found {}

impl ser::Error for Found {
    fn custom<T: std::fmt::Display>(_: T) -> Self {
        Found(None)
    }
}

/// The visitor: `path` holds the segments down to the current value (`.name` or `[k]`).
struct Check<'p> {
    path: &'p mut Vec<String>,
    allow: Allow,
}

impl Check<'_> {
    fn number(self, value: f64) -> Result<(), Found> {
        let fine = value.is_finite()
            || (self.allow == Allow::PlusInfinity && value == f64::INFINITY)
            || (self.allow == Allow::NaN && value.is_nan());
        if fine {
            return Ok(());
        }
        let path = self.path.concat();
        Err(Found(Some(NonFinite {
            path: path.strip_prefix('.').unwrap_or(&path).to_string(),
            value,
        })))
    }

    fn at<T: Serialize + ?Sized>(&mut self, segment: String, v: &T) -> Result<(), Found> {
        self.path.push(segment);
        let r = v.serialize(Check {
            path: &mut *self.path,
            allow: Allow::Finite,
        });
        self.path.pop();
        r
    }
}

/// A part of a list, tuple, map or struct: it counts its elements for their `[k]`.
struct Part<'p> {
    check: Check<'p>,
    next: usize,
}

impl Part<'_> {
    fn element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
        let k = self.next;
        self.next += 1;
        self.check.at(format!("[{k}]"), v)
    }
}

macro_rules! nothing_to_check {
    ($($f:ident: $t:ty),*) => {
        $(fn $f(self, _: $t) -> Result<(), Found> { Ok(()) })*
    };
}

impl<'p> Serializer for Check<'p> {
    type Ok = ();
    type Error = Found;
    type SerializeSeq = Part<'p>;
    type SerializeTuple = Part<'p>;
    type SerializeTupleStruct = Part<'p>;
    type SerializeTupleVariant = Part<'p>;
    type SerializeMap = Part<'p>;
    type SerializeStruct = Part<'p>;
    type SerializeStructVariant = Part<'p>;

    nothing_to_check!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16,
        serialize_i32: i32, serialize_i64: i64, serialize_u8: u8, serialize_u16: u16,
        serialize_u32: u32, serialize_u64: u64, serialize_char: char, serialize_str: &str,
        serialize_bytes: &[u8], serialize_unit_struct: &'static str);

    fn serialize_f32(self, v: f32) -> Result<(), Found> {
        self.number(v as f64)
    }
    fn serialize_f64(self, v: f64) -> Result<(), Found> {
        self.number(v)
    }
    fn serialize_none(self) -> Result<(), Found> {
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<(), Found> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), Found> {
        Ok(())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Result<(), Found> {
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        name: &'static str,
        v: &T,
    ) -> Result<(), Found> {
        let allow = match name {
            UNBOUNDED => Allow::PlusInfinity,
            ABSENT => Allow::NaN,
            _ => self.allow,
        };
        v.serialize(Check {
            path: self.path,
            allow,
        })
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        mut self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        v: &T,
    ) -> Result<(), Found> {
        self.at(format!(".{variant}"), v)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Part<'p>, Found> {
        Ok(Part {
            check: self,
            next: 0,
        })
    }
    fn serialize_tuple(self, _: usize) -> Result<Part<'p>, Found> {
        self.serialize_seq(None)
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Part<'p>, Found> {
        self.serialize_seq(None)
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Part<'p>, Found> {
        self.path.push(format!(".{variant}"));
        self.serialize_seq(None)
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Part<'p>, Found> {
        self.serialize_seq(None)
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Part<'p>, Found> {
        self.serialize_seq(None)
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Part<'p>, Found> {
        self.path.push(format!(".{variant}"));
        self.serialize_seq(None)
    }
}

/// A list's, a tuple's and a tuple struct's elements, each named by its place; a tuple
/// variant's too, which pops its `.variant` segment at the end.
macro_rules! elements {
    ($($trait:ident :: $method:ident, pop = $pop:expr);*) => {$(
        impl ser::$trait for Part<'_> {
            type Ok = ();
            type Error = Found;
            fn $method<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
                self.element(v)
            }
            fn end(self) -> Result<(), Found> {
                if $pop {
                    self.check.path.pop();
                }
                Ok(())
            }
        }
    )*};
}

elements!(
    SerializeSeq::serialize_element, pop = false;
    SerializeTuple::serialize_element, pop = false;
    SerializeTupleStruct::serialize_field, pop = false;
    SerializeTupleVariant::serialize_field, pop = true
);

impl ser::SerializeMap for Part<'_> {
    type Ok = ();
    type Error = Found;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Found> {
        // The key names the next value: its JSON text without quotes.
        let name = serde_json::to_string(key).unwrap_or_default();
        self.check.path.push(format!(".{}", name.trim_matches('"')));
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
        let r = v.serialize(Check {
            path: &mut *self.check.path,
            allow: Allow::Finite,
        });
        self.check.path.pop();
        r
    }
    fn end(self) -> Result<(), Found> {
        Ok(())
    }
}

/// A struct's fields, each named by its name; a struct variant's too, which pops its
/// `.variant` segment at the end.
macro_rules! fields {
    ($($trait:ident, pop = $pop:expr);*) => {$(
        impl ser::$trait for Part<'_> {
            type Ok = ();
            type Error = Found;
            fn serialize_field<T: Serialize + ?Sized>(
                &mut self,
                name: &'static str,
                v: &T,
            ) -> Result<(), Found> {
                self.check.at(format!(".{name}"), v)
            }
            fn end(self) -> Result<(), Found> {
                if $pop {
                    self.check.path.pop();
                }
                Ok(())
            }
        }
    )*};
}

fields!(SerializeStruct, pop = false; SerializeStructVariant, pop = true);

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize)]
    struct Zone {
        change_pct: Option<f64>,
        #[serde(serialize_with = "unbounded")]
        lambda_min: f64,
        #[serde(serialize_with = "absent_each")]
        ratio: Vec<f64>,
    }

    #[derive(serde::Serialize)]
    struct Report {
        rpm: f64,
        zones: Vec<Zone>,
        by_name: std::collections::BTreeMap<String, f64>,
    }

    fn report() -> Report {
        Report {
            rpm: 2000.0,
            zones: vec![
                Zone {
                    change_pct: Some(-3.0),
                    lambda_min: 4.0,
                    ratio: vec![1.0],
                },
                Zone {
                    change_pct: None,
                    lambda_min: f64::INFINITY,
                    ratio: vec![f64::NAN, 0.9],
                },
            ],
            by_name: [("a".to_string(), 1.0)].into(),
        }
    }

    #[test]
    fn a_finite_report_and_its_marked_answers_pass() {
        assert_eq!(first_non_finite(&report()), None);
    }

    #[test]
    fn the_first_number_that_is_not_finite_is_named_by_its_path() {
        let mut r = report();
        r.zones[1].change_pct = Some(f64::NAN);
        let found = first_non_finite(&r).unwrap();
        assert_eq!(found.to_string(), "zones[1].change_pct = NaN");
        let mut r = report();
        r.by_name.insert("b".into(), f64::NEG_INFINITY);
        assert_eq!(
            first_non_finite(&r).unwrap().to_string(),
            "by_name.b = -inf"
        );
    }

    #[test]
    fn a_marker_allows_only_its_own_non_finite_number() {
        let mut r = report();
        r.zones[0].lambda_min = f64::NAN;
        assert_eq!(
            first_non_finite(&r).unwrap().to_string(),
            "zones[0].lambda_min = NaN"
        );
        let mut r = report();
        r.zones[0].ratio[0] = f64::INFINITY;
        assert_eq!(
            first_non_finite(&r).unwrap().to_string(),
            "zones[0].ratio[0] = inf"
        );
    }

    #[test]
    fn markers_change_no_json() {
        let r = report();
        let json = serde_json::to_string(&r).unwrap();
        assert!(json.contains(r#""lambda_min":null"#), "{json}");
        assert!(json.contains(r#""ratio":[null,0.9]"#), "{json}");
    }
}
