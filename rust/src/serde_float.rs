//! Serde for `f64` fields that may be infinite (a switch turned off, no bound, no gap limit):
//! JSON has no infinity, so in a human-readable format those are written as the strings `"inf"`
//! and `"-inf"` (and NaN as `"nan"`); finite values stay numbers. A binary format (postcard,
//! bincode: what a small target stores its state in) writes every float as one, and reads it
//! back as one: such formats cannot say what comes next (`deserialize_any`), and refused every
//! state. Use with `#[serde(with = "crate::serde_float")]`.

use core::fmt;
use serde::de::{self, Visitor};
use serde::{Deserializer, Serializer};

/// Writes `value` as a number, or as `"inf"`, `"-inf"` or `"nan"`.
pub(crate) fn serialize<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    match *value {
        v if !serializer.is_human_readable() => serializer.serialize_f64(v),
        v if v.is_finite() => serializer.serialize_f64(v),
        v if v > 0.0 => serializer.serialize_str("inf"),
        v if v < 0.0 => serializer.serialize_str("-inf"),
        _ => serializer.serialize_str("nan"),
    }
}

/// Reads what [`serialize`] writes.
pub(crate) fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    if deserializer.is_human_readable() {
        deserializer.deserialize_any(FloatVisitor)
    } else {
        deserializer.deserialize_f64(FloatVisitor)
    }
}

struct FloatVisitor;

impl Visitor<'_> for FloatVisitor {
    type Value = f64;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a number, \"inf\", \"-inf\" or \"nan\"")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<f64, E> {
        match v {
            "inf" => Ok(f64::INFINITY),
            "-inf" => Ok(f64::NEG_INFINITY),
            "nan" => Ok(f64::NAN),
            _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
        }
    }
}
