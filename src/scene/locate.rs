//! Finds where a value sits in scene text (`blocks[3]`, `analysis.dt`,
//! `materials["rock"]`) so semantic errors can give a line and column.
//!
//! RON's own parser walks the text, led by the path through serde's
//! self-describing `deserialize_any`; at the value sought the walk stops
//! with an error, whose span is where the parser stands.

use std::fmt;

use serde::de::{self, DeserializeSeed, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde::Deserializer;

/// A place as errors name it, written in dots: `blocks[1].width` as
/// `blocks.1.width`, `materials["rock"].density` as
/// `materials.rock.density`; a dotted path stays as it is. Studies and the
/// Python package read a path through it, so either way names one field.
pub fn dotted_path(place: &str) -> String {
    place
        .replace("[\"", ".")
        .replace("\"]", "")
        .replace('[', ".")
        .replace(']', "")
}

/// One step of a path into the scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seg {
    /// A struct field (or a variant's field) by name.
    Field(String),
    /// An element of a list or tuple.
    Index(usize),
    /// A map entry by its string key.
    Key(String),
}

/// A path into the scene, like `blocks[2].vertices[1]`: the steps it is
/// located by, and how it reads, which leaves out any it is only located by
/// (`blocks[3]` pointing at its face 2) and may end in a note (`blocks[0]
/// (voussoir 3)`).
#[derive(Debug, Clone, Default)]
pub(crate) struct Place {
    segs: Vec<Seg>,
    shown: String,
}

impl Place {
    pub fn root() -> Self {
        Self::default()
    }

    fn with(&self, seg: Seg) -> Self {
        let mut p = self.clone();
        p.shown += &match &seg {
            Seg::Field(name) if p.segs.is_empty() => name.clone(),
            Seg::Field(name) => format!(".{name}"),
            Seg::Index(k) => format!("[{k}]"),
            Seg::Key(k) => format!("[{k:?}]"),
        };
        p.segs.push(seg);
        p
    }

    pub fn field(&self, name: &str) -> Self {
        self.with(Seg::Field(name.to_string()))
    }

    pub fn index(&self, k: usize) -> Self {
        self.with(Seg::Index(k))
    }

    pub fn key(&self, k: &str) -> Self {
        self.with(Seg::Key(k.to_string()))
    }

    /// `field[k]` inside this place, used for the line and column only:
    /// the place still reads as this one.
    pub fn pointing_at(&self, field: &str, k: usize) -> Self {
        let mut p = self.clone();
        p.segs
            .extend([Seg::Field(field.to_string()), Seg::Index(k)]);
        p
    }

    pub fn segs(&self) -> &[Seg] {
        &self.segs
    }
}

/// `blocks[k]`, with the part for a generated block, like `blocks[0]
/// (voussoir 3)`.
pub(super) fn place_of(entry: usize, part: Option<&str>) -> Place {
    let mut at = Place::root().field("blocks").index(entry);
    if let Some(part) = part {
        at.shown += &format!(" ({part})");
    }
    at
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.shown)
    }
}

/// Line and column (1-based) of the value at `place`, or of the deepest
/// part of it that can be found; `None` if not even the first step is
/// found.
pub fn locate(text: &str, place: &Place) -> Option<(usize, usize)> {
    let path = place.segs();
    (1..=path.len())
        .rev()
        .find_map(|n| locate_exact(text, &path[..n]))
}

/// Line and column of the value at `path` if every step of it is written.
pub fn locate_exact(text: &str, path: &[Seg]) -> Option<(usize, usize)> {
    if path.is_empty() {
        return None;
    }
    let mut parser = ron::Deserializer::from_str_with_options(text, &super::ron_options()).ok()?;
    let stop = Walk(path).deserialize(&mut parser).err()?;
    let e = parser.span_error(stop);
    // A field or key stops once it is read, so the span starts on its name;
    // an element stops before it is read, so the span ends at its start.
    let (start, end) = ((e.span.start.line, e.span.start.col), e.span.end);
    match e.code {
        ron::Error::Message(m) if m == AT_VALUE => Some((end.line, end.col)),
        ron::Error::Message(m) if m == AT_NAME => match path.last() {
            Some(Seg::Key(_)) => Some(opening_quote(text, start)),
            _ => Some(start),
        },
        _ => None,
    }
}

/// Where a string key starts (its `"`, or the `r` of `r#"`), from the
/// position just inside its opening quote, where the parser's span starts.
fn opening_quote(text: &str, (line, col): (usize, usize)) -> (usize, usize) {
    let line_text = text.lines().nth(line - 1).unwrap_or_default();
    let before: Vec<char> = line_text.chars().take(col.saturating_sub(2)).collect();
    let hashes = before.iter().rev().take_while(|c| **c == '#').count();
    let raw = before.len() > hashes && before[before.len() - hashes - 1] == 'r';
    (line, col - if raw { 2 + hashes } else { 1 })
}

const AT_NAME: &str = "located at a name";
const AT_VALUE: &str = "located at a value";

/// What is left of the path at a value.
struct Walk<'p>(&'p [Seg]);

impl<'de> DeserializeSeed<'de> for Walk<'_> {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        if self.0.is_empty() {
            return Err(de::Error::custom(AT_VALUE));
        }
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Walk<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a struct, map, list or tuple")
    }

    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }

    fn visit_newtype_struct<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        if let Some((Seg::Field(name) | Seg::Key(name), rest)) = self.0.split_first() {
            while let Some(key) = map.next_key::<String>()? {
                if key == *name && rest.is_empty() {
                    return Err(de::Error::custom(AT_NAME));
                } else if key == *name {
                    return map.next_value_seed(Walk(rest));
                }
                map.next_value::<IgnoredAny>()?;
            }
        }
        Err(de::Error::custom("not written"))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        if let Some((Seg::Index(k), rest)) = self.0.split_first() {
            for _ in 0..*k {
                if seq.next_element::<IgnoredAny>()?.is_none() {
                    break;
                }
            }
            seq.next_element_seed(Walk(rest))?;
        }
        Err(de::Error::custom("not written"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r##"// a scene
#![enable(implicit_some)]
Scene(
    analysis: (duration: 1.0, /* dt: 3, */ dt: 0.5),
    materials: { "a, b": (density: 1.0), "rock": (young: 2.0), r#"sand"#: (poisson: 0.3) },
    blocks: [
        Polygon(material: "x(", vertices: [(0, 0), (1, 0), (1, 1)]),
        // blocks: [ Rectangle ]
        Rectangle(center: (0, 0), width: 1, height: 2),
    ],
)
"##;

    /// Line and column of the last occurrence of `needle` on `line`.
    fn at(line: usize, needle: &str) -> Option<(usize, usize)> {
        let text = TEXT.lines().nth(line - 1).unwrap();
        Some((
            line,
            text[..text.rfind(needle).unwrap()].chars().count() + 1,
        ))
    }

    #[test]
    fn finds_fields_elements_and_keys() {
        let root = Place::root();
        let (analysis, blocks) = (root.field("analysis"), root.field("blocks"));
        let rock = root.field("materials").key("rock");
        let find = |place: &Place| locate(TEXT, place);
        assert_eq!(find(&analysis.field("dt")), at(4, "dt"));
        assert_eq!(find(&blocks.index(0)), at(7, "Polygon"));
        assert_eq!(find(&blocks.index(1)), at(9, "Rectangle"));
        assert_eq!(find(&blocks.index(1).field("width")), at(9, "width"));
        let corner = blocks.index(0).field("vertices").index(2);
        assert_eq!(find(&corner), at(7, "(1, 1)"));
        assert_eq!(find(&rock), at(5, "\"rock\""));
        assert_eq!(find(&rock.field("young")), at(5, "young"));
        let sand = root.field("materials").key("sand");
        assert_eq!(find(&sand), at(5, "r#\"sand"));
        // Missing parts fall back to the deepest found; a hidden part is
        // located, not shown.
        assert_eq!(find(&blocks.index(5)), at(6, "blocks"));
        assert_eq!(find(&root.field("loads").index(0)), None);
        let hidden = blocks.index(0).pointing_at("vertices", 2);
        assert_eq!(hidden.to_string(), "blocks[0]");
        assert_eq!(find(&hidden), at(7, "(1, 1)"));
        // Exactly: only when every step is written.
        let exact = |place: Place| locate_exact(TEXT, place.segs());
        assert_eq!(exact(analysis.field("dt")), at(4, "dt"));
        assert_eq!(exact(analysis.field("plane")), None);
        assert_eq!(exact(blocks.index(5)), None);
    }
}
