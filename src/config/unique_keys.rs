//! A map field that refuses a key written twice. serde's `BTreeMap` keeps the last value of a
//! repeated key without a word, so a scene with two materials named alike would silently lose
//! the first; this deserializer stops at the second with the name (RON adds the position).

use serde::de::{Deserialize, Deserializer, Error, MapAccess, Visitor};
use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;

/// `#[serde(deserialize_with = "unique_keys::materials")]` on a `BTreeMap<String, V>`.
pub fn materials<'de, D, V>(d: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct Unique<V>(PhantomData<V>);

    impl<'de, V: Deserialize<'de>> Visitor<'de> for Unique<V> {
        type Value = BTreeMap<String, V>;

        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("a map of material names to materials, e.g. { \"grey\": Diffuse() }")
        }

        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(key) = map.next_key::<String>()? {
                if out.contains_key(&key) {
                    return Err(A::Error::custom(format!(
                        "materials: \"{key}\" is defined twice; give each material its own name"
                    )));
                }
                let value = map.next_value()?;
                out.insert(key, value);
            }
            Ok(out)
        }
    }

    d.deserialize_map(Unique(PhantomData))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    #[test]
    fn duplicate_material_is_refused_with_its_name_and_line() {
        let text = "(materials: {\n \"a\": Diffuse(),\n \"b\": Diffuse(),\n \"a\": Diffuse(reflectance: Constant(0.9)),\n})";
        let e = crate::config::parse_str(text, Path::new("s.ron")).unwrap_err();
        assert!(e.message.contains("\"a\" is defined twice"), "{e}");
        assert_eq!(e.position.map(|p| p.0), Some(4), "{e}");
        let ok = crate::config::parse_str(
            "(materials: {\"a\": Diffuse(), \"b\": Diffuse()})",
            Path::new("s.ron"),
        );
        assert_eq!(ok.unwrap().materials.len(), 2);
    }
}
