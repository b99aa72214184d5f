//! Scene fields by path: the scene's RON text as a tree that keeps struct
//! and variant names (`ron::Value` drops them, so `Rectangle(...)` could not
//! be written back), and `set` that replaces one value's text in place.
//!
//! A path is dot-separated: field names in structs and variants
//! (`analysis.dt`, `default_joint.friction_angle`), indices in lists and
//! tuples (`blocks.0.thickness`), keys in maps (`materials.rock.kind`).

use std::ops::Range;

/// One value of the text and where it is.
#[derive(Debug, Clone)]
enum Node {
    /// `Name(a: 1, b: 2)` or `(a: 1)`; `open` is the byte after `(`.
    Struct {
        fields: Vec<(String, Node)>,
        open: usize,
        span: Range<usize>,
    },
    /// `(1, 2)`, `[1, 2]`, `Name(1, 2)`.
    List {
        items: Vec<Node>,
        span: Range<usize>,
    },
    /// `{"a": 1}`.
    Map {
        entries: Vec<(String, Node)>,
        span: Range<usize>,
    },
    /// A number, string, identifier or unit.
    Leaf { span: Range<usize> },
}

impl Node {
    fn span(&self) -> Range<usize> {
        match self {
            Node::Struct { span, .. }
            | Node::List { span, .. }
            | Node::Map { span, .. }
            | Node::Leaf { span } => span.clone(),
        }
    }
}

/// Why a path does not lead to a value: the part that failed and what is there.
#[derive(Debug, Clone, PartialEq)]
pub struct PathError {
    /// The path up to the segment that failed.
    pub at: String,
    pub message: String,
}

/// Sets the value at `path` in the RON `text` to `value` (RON text); a
/// field missing from a struct is added. Returns the new text.
pub fn set(text: &str, path: &str, value: &str) -> Result<String, PathError> {
    let root = parse(text).map_err(|message| PathError {
        at: String::new(),
        message,
    })?;
    let mut node = &root;
    let segments: Vec<&str> = path.split('.').collect();
    for (k, seg) in segments.iter().enumerate() {
        let here = segments[..k].join(".");
        let here_name = if here.is_empty() {
            "the scene".to_string()
        } else {
            format!("`{here}`")
        };
        let last = k + 1 == segments.len();
        let fail = |message: String| PathError {
            at: segments[..=k].join("."),
            message,
        };
        node = match node {
            Node::Struct { fields, open, .. } => match fields.iter().find(|(n, _)| n == seg) {
                Some((_, child)) => child,
                None if last => {
                    let mut out = text.to_string();
                    out.insert_str(*open, &format!("{seg}: {value}, "));
                    return Ok(out);
                }
                None => {
                    let names: Vec<&str> = fields.iter().map(|(n, _)| n.as_str()).collect();
                    return Err(fail(format!(
                        "{here_name} has no field `{seg}` written; its fields are {}",
                        names.join(", ")
                    )));
                }
            },
            Node::List { items, .. } => {
                match seg.parse::<usize>().ok().and_then(|i| items.get(i)) {
                    Some(child) => child,
                    None => {
                        return Err(fail(format!(
                            "{here_name} is a list of {} entries: give an index from 0 to {}",
                            items.len(),
                            items.len().saturating_sub(1)
                        )))
                    }
                }
            }
            Node::Map { entries, .. } => match entries.iter().find(|(n, _)| n == seg) {
                Some((_, child)) => child,
                None => {
                    let names: Vec<&str> = entries.iter().map(|(n, _)| n.as_str()).collect();
                    return Err(fail(format!(
                        "{here_name} has no key `{seg}`; its keys are {}",
                        names.join(", ")
                    )));
                }
            },
            Node::Leaf { span } => {
                return Err(fail(format!(
                    "{here_name} is a single value ({}), not a group of fields",
                    &text[span.clone()]
                )))
            }
        };
    }
    let span = node.span();
    let mut out = String::with_capacity(text.len() + value.len());
    out.push_str(&text[..span.start]);
    out.push_str(value);
    out.push_str(&text[span.end..]);
    Ok(out)
}

/// The text of the value at `path`, if there is one.
pub fn get(text: &str, path: &str) -> Option<String> {
    let mut node = &parse(text).ok()?;
    for seg in path.split('.') {
        node = match node {
            Node::Struct { fields, .. } => &fields.iter().find(|(n, _)| n == seg)?.1,
            Node::List { items, .. } => items.get(seg.parse::<usize>().ok()?)?,
            Node::Map { entries, .. } => &entries.iter().find(|(n, _)| n == seg)?.1,
            Node::Leaf { .. } => return None,
        };
    }
    Some(text[node.span()].to_string())
}

fn parse(text: &str) -> Result<Node, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        at: 0,
    };
    let node = p.value()?;
    p.blank();
    if p.at != p.s.len() {
        return Err(p.unexpected("the end of the scene"));
    }
    Ok(node)
}

struct Parser<'a> {
    s: &'a [u8],
    at: usize,
}

impl Parser<'_> {
    /// Skips white space and comments.
    fn blank(&mut self) {
        loop {
            while self.at < self.s.len() && self.s[self.at].is_ascii_whitespace() {
                self.at += 1;
            }
            if self.s[self.at..].starts_with(b"//") {
                while self.at < self.s.len() && self.s[self.at] != b'\n' {
                    self.at += 1;
                }
            } else if self.s[self.at..].starts_with(b"#!") {
                // `#![enable(...)]` extension attributes.
                while self.at < self.s.len() && self.s[self.at] != b']' {
                    self.at += 1;
                }
                self.at += 1;
            } else if self.s[self.at..].starts_with(b"/*") {
                let end =
                    find(&self.s[self.at + 2..], b"*/").map_or(self.s.len(), |k| self.at + k + 4);
                self.at = end;
            } else {
                return;
            }
        }
    }

    fn peek(&self) -> Option<u8> {
        self.s.get(self.at).copied()
    }

    fn unexpected(&self, wanted: &str) -> String {
        let line = self.s[..self.at.min(self.s.len())]
            .iter()
            .filter(|&&c| c == b'\n')
            .count()
            + 1;
        format!("line {line}: expected {wanted}")
    }

    fn ident(&mut self) -> Option<String> {
        let start = self.at;
        while self
            .peek()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_')
        {
            self.at += 1;
        }
        (self.at > start).then(|| String::from_utf8_lossy(&self.s[start..self.at]).into_owned())
    }

    fn value(&mut self) -> Result<Node, String> {
        self.blank();
        let start = self.at;
        match self.peek() {
            Some(b'"') => {
                self.string()?;
                Ok(Node::Leaf {
                    span: start..self.at,
                })
            }
            Some(b'\'') => {
                self.at += 1;
                while self.peek().is_some_and(|c| c != b'\'') {
                    self.at += if self.peek() == Some(b'\\') { 2 } else { 1 };
                }
                self.at += 1;
                Ok(Node::Leaf {
                    span: start..self.at,
                })
            }
            Some(b'[') => {
                self.at += 1;
                let items = self.items(b']')?;
                Ok(Node::List {
                    items,
                    span: start..self.at,
                })
            }
            Some(b'{') => {
                self.at += 1;
                let mut entries = Vec::new();
                loop {
                    self.blank();
                    if self.peek() == Some(b'}') {
                        self.at += 1;
                        break;
                    }
                    let key = self.value()?;
                    let key = text_key(&self.s[key.span()]);
                    self.blank();
                    if self.peek() != Some(b':') {
                        return Err(self.unexpected("`:` after a map key"));
                    }
                    self.at += 1;
                    entries.push((key, self.value()?));
                    self.comma(b'}')?;
                }
                Ok(Node::Map {
                    entries,
                    span: start..self.at,
                })
            }
            Some(b'(') => self.group(start),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                self.ident();
                if self.peek() == Some(b'(') {
                    self.group(start)
                } else {
                    Ok(Node::Leaf {
                        span: start..self.at,
                    })
                }
            }
            Some(c) if c.is_ascii_digit() || matches!(c, b'-' | b'+' | b'.') => {
                while self.peek().is_some_and(|c| {
                    c.is_ascii_alphanumeric() || matches!(c, b'-' | b'+' | b'.' | b'_')
                }) {
                    self.at += 1;
                }
                Ok(Node::Leaf {
                    span: start..self.at,
                })
            }
            _ => Err(self.unexpected("a value")),
        }
    }

    fn string(&mut self) -> Result<(), String> {
        self.at += 1;
        while let Some(c) = self.peek() {
            self.at += 1;
            match c {
                b'\\' => self.at += 1,
                b'"' => return Ok(()),
                _ => {}
            }
        }
        Err(self.unexpected("the end of a string"))
    }

    /// `(` at `self.at`: named fields, or a tuple; `start` includes a name.
    fn group(&mut self, start: usize) -> Result<Node, String> {
        self.at += 1;
        let open = self.at;
        // Named fields when the first entry is `ident :`.
        let save = self.at;
        self.blank();
        let named = self.ident().is_some() && {
            self.blank();
            self.peek() == Some(b':')
        };
        self.at = save;
        if !named {
            let items = self.items(b')')?;
            return Ok(Node::List {
                items,
                span: start..self.at,
            });
        }
        let mut fields = Vec::new();
        loop {
            self.blank();
            if self.peek() == Some(b')') {
                self.at += 1;
                break;
            }
            let name = self
                .ident()
                .ok_or_else(|| self.unexpected("a field name"))?;
            self.blank();
            if self.peek() != Some(b':') {
                return Err(self.unexpected("`:` after a field name"));
            }
            self.at += 1;
            fields.push((name, self.value()?));
            self.comma(b')')?;
        }
        Ok(Node::Struct {
            fields,
            open,
            span: start..self.at,
        })
    }

    fn items(&mut self, close: u8) -> Result<Vec<Node>, String> {
        let mut items = Vec::new();
        loop {
            self.blank();
            if self.peek() == Some(close) {
                self.at += 1;
                return Ok(items);
            }
            items.push(self.value()?);
            self.comma(close)?;
        }
    }

    /// A `,` or the closing bracket (left for the caller).
    fn comma(&mut self, close: u8) -> Result<(), String> {
        self.blank();
        match self.peek() {
            Some(b',') => {
                self.at += 1;
                Ok(())
            }
            Some(c) if c == close => Ok(()),
            _ => Err(self.unexpected(&format!("`,` or `{}`", close as char))),
        }
    }
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// A map key as a path segment: strings without their quotes.
fn text_key(raw: &[u8]) -> String {
    let s = String::from_utf8_lossy(raw);
    s.trim_matches('"').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = r#"#![enable(implicit_some)]
Scene(
    analysis: (duration: 1.0, dt: None),
    materials: {"rock": (density: 2700.0)},
    default_joint: Coulomb(friction_angle: 20.0),
    blocks: [Rectangle(center: (0.0, 0.0), width: 1.0), Arch(thickness: 1.1)],
)"#;

    #[test]
    fn sets_fields_entries_and_keys() {
        let t = set(SCENE, "analysis.dt", "0.01").unwrap();
        assert_eq!(get(&t, "analysis.dt").unwrap(), "0.01");
        let t = set(&t, "default_joint.friction_angle", "31.5").unwrap();
        assert_eq!(get(&t, "default_joint.friction_angle").unwrap(), "31.5");
        let t = set(&t, "blocks.1.thickness", "0.9").unwrap();
        assert_eq!(get(&t, "blocks.1.thickness").unwrap(), "0.9");
        assert!(t.contains("Rectangle(center: (0.0, 0.0)"));
        let t = set(&t, "materials.rock.kind", "Rigid").unwrap();
        assert_eq!(get(&t, "materials.rock.kind").unwrap(), "Rigid");
        let t = set(&t, "blocks.0.center.1", "2.0").unwrap();
        assert_eq!(get(&t, "blocks.0.center").unwrap(), "(0.0, 2.0)");
    }

    #[test]
    fn bad_paths_say_what_is_there() {
        let e = set(SCENE, "analysis.dt.x", "1").unwrap_err();
        assert!(e.message.contains("single value"), "{e:?}");
        let e = set(SCENE, "blocks.5.width", "1").unwrap_err();
        assert!(e.message.contains("0 to 1"), "{e:?}");
        let e = set(SCENE, "analyses.dt", "1").unwrap_err();
        assert!(e.message.contains("analysis, materials"), "{e:?}");
    }
}
