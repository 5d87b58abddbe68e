//! [`Typed`]: a table whose `type` key selects what the rest of it holds (`[[shapes]]`,
//! `[materials.NAME]`, `[[lights]]`), read without buffering it.
//!
//! serde's internally tagged enums (`#[serde(tag = "type")]`) buffer the whole table before
//! reading it, which loses the position of every value inside: an error in a shape's `radius`
//! was reported at the `[[shapes]]` line. Here the `type` is read first and the rest of the
//! table goes straight to the variant, so the TOML parser reports each error at its value. The
//! enum itself derives serde's (externally tagged) `Deserialize`; [`Typed`] feeds it the
//! variant named by `type` and the remaining keys as that variant's fields.
//!
//! A table whose `type` is not its first key is read too, through a copy without positions
//! (its errors then point at the table's line).

use std::fmt;
use std::marker::PhantomData;

use serde::de::value::{MapDeserializer, StringDeserializer};
use serde::de::{self, DeserializeSeed, EnumAccess, IntoDeserializer, MapAccess, VariantAccess, Visitor};
use serde::{Deserialize, Deserializer};

/// An enum deserialized from a table with a `type` key (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Typed<T>(pub T);

/// An enum of table kinds: the `type` values it accepts, for the error that lists them.
pub trait TypeNames {
    /// The accepted `type` values.
    const TYPES: &'static [&'static str];
}

impl<'de, T: Deserialize<'de> + TypeNames> Deserialize<'de> for Typed<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_map(TypedVisitor(PhantomData))
    }
}

struct TypedVisitor<T>(PhantomData<T>);

impl<'de, T: Deserialize<'de> + TypeNames> Visitor<'de> for TypedVisitor<T> {
    type Value = Typed<T>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a table with a `type` key, one of {}", T::TYPES.join(", "))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let Some(first) = map.next_key::<String>()? else {
            return Err(de::Error::missing_field("type"));
        };
        if first == "type" {
            // Checked while the value is read, so that an unknown type is reported at it.
            let kind = map.next_value_seed(KindSeed(T::TYPES))?;
            return T::deserialize(TypedTable { kind, map }).map(Typed);
        }
        // `type` comes later: copy the table (positions are lost) and read the copy.
        let mut entries: Vec<(String, toml::Value)> = vec![(first, map.next_value()?)];
        while let Some(key) = map.next_key::<String>()? {
            entries.push((key.clone(), map.next_value()?));
        }
        let Some(at) = entries.iter().position(|(key, _)| key == "type") else {
            return Err(de::Error::missing_field("type"));
        };
        let (_, kind) = entries.remove(at);
        let kind = match kind {
            toml::Value::String(kind) if T::TYPES.contains(&kind.as_str()) => kind,
            toml::Value::String(kind) => return Err(de::Error::unknown_variant(&kind, T::TYPES)),
            other => return Err(de::Error::invalid_type(unexpected(&other), &"a string")),
        };
        let rest: MapDeserializer<'de, _, toml::de::Error> = MapDeserializer::new(entries.into_iter());
        T::deserialize(TypedTable { kind, map: rest }).map(Typed).map_err(|e| de::Error::custom(e.message()))
    }
}

/// What a buffered value is, for a type error.
fn unexpected(value: &toml::Value) -> de::Unexpected<'_> {
    match value {
        toml::Value::Integer(i) => de::Unexpected::Signed(*i),
        toml::Value::Float(f) => de::Unexpected::Float(*f),
        toml::Value::Boolean(b) => de::Unexpected::Bool(*b),
        toml::Value::Array(_) => de::Unexpected::Seq,
        toml::Value::Table(_) => de::Unexpected::Map,
        toml::Value::String(s) => de::Unexpected::Str(s),
        toml::Value::Datetime(_) => de::Unexpected::Other("a date-time"),
    }
}

/// Reads a `type` value and checks it against the accepted names.
struct KindSeed(&'static [&'static str]);

impl<'de> DeserializeSeed<'de> for KindSeed {
    type Value = String;
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<String, D::Error> {
        let kind = String::deserialize(deserializer)?;
        if self.0.contains(&kind.as_str()) {
            Ok(kind)
        } else {
            Err(de::Error::unknown_variant(&kind, self.0))
        }
    }
}

/// The variant `kind` with the rest of the table as its fields, presented to an externally
/// tagged enum's derived `Deserialize`.
struct TypedTable<A> {
    kind: String,
    map: A,
}

impl<'de, A: MapAccess<'de>> Deserializer<'de> for TypedTable<A> {
    type Error = A::Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, A::Error> {
        visitor.visit_enum(self)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf option
        unit unit_struct newtype_struct seq tuple tuple_struct map struct enum identifier ignored_any
    }
}

impl<'de, A: MapAccess<'de>> EnumAccess<'de> for TypedTable<A> {
    type Error = A::Error;
    type Variant = Fields<A>;

    fn variant_seed<V: DeserializeSeed<'de>>(self, seed: V) -> Result<(V::Value, Fields<A>), A::Error> {
        let kind: StringDeserializer<A::Error> = self.kind.into_deserializer();
        Ok((seed.deserialize(kind)?, Fields(self.map)))
    }
}

/// The remaining keys of a table as a struct variant's fields.
struct Fields<A>(A);

impl<'de, A: MapAccess<'de>> VariantAccess<'de> for Fields<A> {
    type Error = A::Error;

    fn unit_variant(self) -> Result<(), A::Error> {
        Err(de::Error::invalid_type(de::Unexpected::StructVariant, &"a unit variant"))
    }
    fn newtype_variant_seed<T: DeserializeSeed<'de>>(self, _seed: T) -> Result<T::Value, A::Error> {
        Err(de::Error::invalid_type(de::Unexpected::StructVariant, &"a newtype variant"))
    }
    fn tuple_variant<V: Visitor<'de>>(self, _len: usize, _visitor: V) -> Result<V::Value, A::Error> {
        Err(de::Error::invalid_type(de::Unexpected::StructVariant, &"a tuple variant"))
    }
    fn struct_variant<V: Visitor<'de>>(
        self,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, A::Error> {
        visitor.visit_map(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Deserialize)]
    #[serde(rename_all = "snake_case", deny_unknown_fields)]
    enum Shape {
        Disc { radius: f32 },
        Dot {},
    }

    impl TypeNames for Shape {
        const TYPES: &'static [&'static str] = &["disc", "dot"];
    }

    #[derive(Debug, Deserialize)]
    struct File {
        shapes: Vec<toml::Spanned<Typed<Shape>>>,
    }

    fn error_at(text: &str) -> (usize, String) {
        let error = toml::from_str::<File>(text).expect_err("invalid");
        let offset = error.span().expect("a position").start;
        (text[..offset].matches('\n').count() + 1, error.message().to_owned())
    }

    #[test]
    fn reads_the_variant_named_by_type() {
        let file: File =
            toml::from_str("[[shapes]]\ntype = \"disc\"\nradius = 2\n[[shapes]]\ntype = \"dot\"\n").unwrap();
        assert_eq!(file.shapes[0].get_ref().0, Shape::Disc { radius: 2.0 });
        assert_eq!(file.shapes[1].get_ref().0, Shape::Dot {});
        // `type` need not come first.
        let file: File = toml::from_str("[[shapes]]\nradius = 3\ntype = \"disc\"\n").unwrap();
        assert_eq!(file.shapes[0].get_ref().0, Shape::Disc { radius: 3.0 });
    }

    /// The point of this module: an error inside the table is reported at its value's line (3),
    /// not at the `[[shapes]]` line (1), as serde's tagged enums did.
    #[test]
    fn errors_point_at_the_value_not_the_table() {
        let (line, message) = error_at("[[shapes]]\ntype = \"disc\"\nradius = \"one\"\n");
        assert_eq!(line, 3, "{message}");
        assert!(message.contains("expected f32"), "{message}");
        let (line, message) = error_at("[[shapes]]\ntype = \"cone\"\nradius = 1\n");
        assert_eq!(line, 2, "{message}");
        assert!(
            message.contains("cone") && message.contains("disc, dot") || message.contains("`disc`"),
            "{message}"
        );
        let (_, message) = error_at("[[shapes]]\ntype = \"disc\"\nradius = 1\nradiu = 2\n");
        assert!(message.contains("radiu"), "{message}");
        let (_, message) = error_at("[[shapes]]\ntype = \"disc\"\n");
        assert!(message.contains("missing field `radius`"), "{message}");
        let (_, message) = error_at("[[shapes]]\nradius = 1\n");
        assert!(message.contains("missing field `type`"), "{message}");
    }
}
