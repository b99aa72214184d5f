//! A scene as a tree of RON values that keeps struct and variant names
//! (`ron::Value` drops them, so it cannot be written back as a scene):
//! read and changed by a dotted path, then written as RON text for
//! `Scene::from_str` to parse and check again.

use std::fmt::Write;

use serde::ser::{self, Serialize};

/// One RON value, with the names a scene file needs.
#[derive(Debug, Clone, PartialEq)]
pub enum Node {
    Bool(bool),
    Int(i128),
    Float(f64),
    Char(char),
    Str(String),
    None,
    Some(Box<Node>),
    Unit,
    /// A unit variant or unit struct: `Rigid`.
    Name(String),
    /// A newtype variant `Name(inner)`; one whose inner value is a struct
    /// is written with its fields directly (`Coulomb(friction_angle: 20.0)`).
    Newtype(String, Box<Node>),
    /// A newtype struct `Name(inner)`.
    Wrapped(String, Box<Node>),
    Seq(Vec<Node>),
    /// `(a, b)`, or `Name(a, b)` when named.
    Tuple(Option<String>, Vec<Node>),
    Map(Vec<(Node, Node)>),
    /// `Name(field: value, ...)`.
    Struct(String, Vec<(String, Node)>),
    /// RON text given as it is (a whole value written by hand).
    Raw(String),
}

/// A value given from outside (Python), before it is shaped like the value
/// it replaces.
#[derive(Debug, Clone, PartialEq)]
pub enum Given {
    None,
    Bool(bool),
    Int(i128),
    Float(f64),
    Str(String),
    List(Vec<Given>),
    Dict(Vec<(String, Given)>),
}

/// Why a path does not lead to a value.
#[derive(Debug, Clone, PartialEq)]
pub struct PathError(pub String);

impl std::fmt::Display for PathError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PathError {}

/// The tree of any serialisable value.
pub fn to_tree<T: Serialize>(value: &T) -> Node {
    value
        .serialize(TreeSerializer)
        .expect("building a tree never fails")
}

/// `blocks[1].angle` and `blocks.1.angle` alike, and a key as the
/// scene's errors name it: `materials["rock"].density`.
fn segments(path: &str) -> Vec<String> {
    dda::scene::dotted_path(path)
        .split('.')
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

impl Node {
    /// The value at `path` (dotted: struct fields, map keys, sequence
    /// indices; variants and options are looked through).
    pub fn get(&self, path: &str) -> Result<&Node, PathError> {
        let mut node = self;
        let mut done: Vec<String> = Vec::new();
        for seg in segments(path) {
            node = node.child(&seg, &done)?;
            done.push(seg);
        }
        Ok(node)
    }

    /// Puts `value` at `path`, shaped like the value it replaces. A struct
    /// field not yet there is added (the scene's own check then says
    /// whether it exists).
    pub fn set(&mut self, path: &str, value: &Given) -> Result<(), PathError> {
        let segs = segments(path);
        if segs.is_empty() {
            return Err(PathError("an empty path names no field".into()));
        }
        let mut node = self;
        let mut done: Vec<String> = Vec::new();
        for (k, seg) in segs.iter().enumerate() {
            let last = k + 1 == segs.len();
            if last {
                if let Some(fields) = node.fields_mut() {
                    if !fields.iter().any(|(name, _)| name == seg) {
                        fields.push((seg.clone(), shape_new(value)));
                        return Ok(());
                    }
                }
            }
            node = node.child_mut(seg, &done)?;
            done.push(seg.clone());
        }
        *node = shape(value, Some(node));
        Ok(())
    }

    /// The fields of the struct this node is or wraps.
    fn fields_mut(&mut self) -> Option<&mut Vec<(String, Node)>> {
        match self {
            Node::Struct(_, fields) => Some(fields),
            Node::Some(inner) | Node::Newtype(_, inner) | Node::Wrapped(_, inner) => {
                inner.fields_mut()
            }
            _ => None,
        }
    }

    fn child(&self, seg: &str, done: &[String]) -> Result<&Node, PathError> {
        match self {
            Node::Some(inner) | Node::Newtype(_, inner) | Node::Wrapped(_, inner) => {
                inner.child(seg, done)
            }
            Node::Struct(_, fields) => fields
                .iter()
                .find(|(name, _)| name == seg)
                .map(|(_, v)| v)
                .ok_or_else(|| self.missing(seg, done)),
            Node::Map(entries) => entries
                .iter()
                .find(|(key, _)| key.key_text() == seg)
                .map(|(_, v)| v)
                .ok_or_else(|| self.missing(seg, done)),
            Node::Seq(items) | Node::Tuple(_, items) => {
                let k = index(seg, items.len(), done)?;
                Ok(&items[k])
            }
            _ => Err(self.missing(seg, done)),
        }
    }

    fn child_mut(&mut self, seg: &str, done: &[String]) -> Result<&mut Node, PathError> {
        let error = self.missing(seg, done);
        match self {
            Node::Some(inner) | Node::Newtype(_, inner) | Node::Wrapped(_, inner) => {
                inner.child_mut(seg, done)
            }
            Node::Struct(_, fields) => fields
                .iter_mut()
                .find(|(name, _)| name == seg)
                .map(|(_, v)| v)
                .ok_or(error),
            Node::Map(entries) => entries
                .iter_mut()
                .find(|(key, _)| key.key_text() == seg)
                .map(|(_, v)| v)
                .ok_or(error),
            Node::Seq(items) | Node::Tuple(_, items) => {
                let k = index(seg, items.len(), done)?;
                Ok(&mut items[k])
            }
            _ => Err(error),
        }
    }

    /// What a path segment names in a map: the key's text, unquoted.
    fn key_text(&self) -> String {
        match self {
            Node::Str(s) | Node::Name(s) => s.clone(),
            other => other.to_ron(),
        }
    }

    /// The error for a segment this node does not have, listing what it has.
    fn missing(&self, seg: &str, done: &[String]) -> PathError {
        let here = if done.is_empty() {
            "the scene".to_string()
        } else {
            format!("`{}`", done.join("."))
        };
        let names: Vec<String> = match self {
            Node::Some(inner) | Node::Newtype(_, inner) | Node::Wrapped(_, inner) => {
                return inner.missing(seg, done)
            }
            Node::Struct(_, fields) => fields.iter().map(|(n, _)| n.clone()).collect(),
            Node::Map(entries) => entries.iter().map(|(k, _)| k.key_text()).collect(),
            _ => Vec::new(),
        };
        if names.is_empty() {
            PathError(format!(
                "{here} is a single value ({}), it has no `{seg}`",
                self.to_ron()
            ))
        } else {
            PathError(format!(
                "{here} has no `{seg}`; it has: {}",
                names.join(", ")
            ))
        }
    }

    /// Rewrites every relative `path` of a `Record` (a ground-motion file)
    /// as seen from `dir`, so the scene reads the same file once it is no
    /// longer parsed from its own folder.
    pub fn anchor_files(&mut self, dir: &std::path::Path) {
        match self {
            Node::Newtype(name, inner) if name == "Record" => {
                if let Node::Struct(_, fields) = inner.as_mut() {
                    anchor_path(fields, dir);
                }
                inner.anchor_files(dir);
            }
            Node::Struct(name, fields) => {
                if name == "Record" {
                    anchor_path(fields, dir);
                }
                fields.iter_mut().for_each(|(_, v)| v.anchor_files(dir));
            }
            Node::Some(inner) | Node::Newtype(_, inner) | Node::Wrapped(_, inner) => {
                inner.anchor_files(dir)
            }
            Node::Seq(items) | Node::Tuple(_, items) => {
                items.iter_mut().for_each(|v| v.anchor_files(dir))
            }
            Node::Map(entries) => entries.iter_mut().for_each(|(_, v)| v.anchor_files(dir)),
            _ => {}
        }
    }

    /// The value as RON text (struct and variant names written, nested
    /// values indented), readable with the scene's RON extensions.
    pub fn to_ron(&self) -> String {
        let mut out = String::new();
        self.write(&mut out, 0);
        out
    }

    fn write(&self, out: &mut String, depth: usize) {
        match self {
            Node::Bool(b) => write!(out, "{b}").unwrap(),
            Node::Int(i) => write!(out, "{i}").unwrap(),
            Node::Float(x) => write_float(out, *x),
            Node::Char(c) => write!(out, "{c:?}").unwrap(),
            Node::Str(s) => write!(out, "{s:?}").unwrap(),
            Node::None => out.push_str("None"),
            // Written bare, as the scene's own writer does (IMPLICIT_SOME).
            Node::Some(inner) => inner.write(out, depth),
            Node::Unit => out.push_str("()"),
            Node::Name(name) => out.push_str(name),
            Node::Wrapped(name, inner) => {
                out.push_str(name);
                out.push('(');
                inner.write(out, depth);
                out.push(')');
            }
            Node::Newtype(name, inner) => match inner.as_ref() {
                Node::Struct(_, fields) => write_fields(out, name, fields, depth),
                other => {
                    out.push_str(name);
                    out.push('(');
                    other.write(out, depth);
                    out.push(')');
                }
            },
            Node::Seq(items) => write_list(out, "[", "]", items.iter(), depth),
            Node::Tuple(name, items) => {
                out.push_str(name.as_deref().unwrap_or(""));
                write_list(out, "(", ")", items.iter(), depth);
            }
            Node::Map(entries) => {
                if entries.is_empty() {
                    out.push_str("{}");
                    return;
                }
                out.push_str("{\n");
                for (key, value) in entries {
                    indent(out, depth + 1);
                    key.write(out, depth + 1);
                    out.push_str(": ");
                    value.write(out, depth + 1);
                    out.push_str(",\n");
                }
                indent(out, depth);
                out.push('}');
            }
            Node::Struct(name, fields) => write_fields(out, name, fields, depth),
            Node::Raw(text) => out.push_str(text),
        }
    }

    /// Whether the value fits on one line: numbers, names and short
    /// lists of them.
    fn is_flat(&self) -> bool {
        match self {
            Node::Seq(items) | Node::Tuple(_, items) => {
                items.len() <= 8 && items.iter().all(Node::is_scalar)
            }
            Node::Some(inner) => inner.is_flat(),
            other => other.is_scalar(),
        }
    }

    fn is_scalar(&self) -> bool {
        matches!(
            self,
            Node::Bool(_)
                | Node::Int(_)
                | Node::Float(_)
                | Node::Char(_)
                | Node::Str(_)
                | Node::None
                | Node::Unit
                | Node::Name(_)
        )
    }
}

fn anchor_path(fields: &mut [(String, Node)], dir: &std::path::Path) {
    for (name, value) in fields.iter_mut() {
        if let (true, Node::Str(path)) = (name == "path", &*value) {
            if std::path::Path::new(path).is_relative() {
                *value = Node::Str(dir.join(path).display().to_string());
            }
        }
    }
}

fn index(seg: &str, len: usize, done: &[String]) -> Result<usize, PathError> {
    let here = done.join(".");
    let k: usize = seg.parse().map_err(|_| {
        PathError(format!(
            "`{here}` is a list: give an index from 0 to {}, not `{seg}`",
            len.saturating_sub(1)
        ))
    })?;
    if k >= len {
        return Err(PathError(format!(
            "`{here}` has {len} entries: index {k} is past its end"
        )));
    }
    Ok(k)
}

fn indent(out: &mut String, depth: usize) {
    for _ in 0..depth {
        out.push_str("    ");
    }
}

/// A float RON reads back to the same number (always with a point or an
/// exponent, so it is not taken for an integer).
fn write_float(out: &mut String, x: f64) {
    if x.is_nan() {
        out.push_str("NaN");
    } else if x.is_infinite() {
        out.push_str(if x > 0.0 { "inf" } else { "-inf" });
    } else {
        write!(out, "{x:?}").unwrap();
    }
}

fn write_fields(out: &mut String, name: &str, fields: &[(String, Node)], depth: usize) {
    out.push_str(name);
    if fields.is_empty() {
        out.push_str("()");
        return;
    }
    if fields.iter().all(|(_, v)| v.is_flat()) && fields.len() <= 4 {
        out.push('(');
        for (k, (field, value)) in fields.iter().enumerate() {
            if k > 0 {
                out.push_str(", ");
            }
            write!(out, "{field}: ").unwrap();
            value.write(out, depth);
        }
        out.push(')');
        return;
    }
    out.push_str("(\n");
    for (field, value) in fields {
        indent(out, depth + 1);
        write!(out, "{field}: ").unwrap();
        value.write(out, depth + 1);
        out.push_str(",\n");
    }
    indent(out, depth);
    out.push(')');
}

fn write_list<'a>(
    out: &mut String,
    open: &str,
    close: &str,
    items: impl ExactSizeIterator<Item = &'a Node>,
    depth: usize,
) {
    let items: Vec<&Node> = items.collect();
    if items.iter().all(|v| v.is_flat()) && items.len() <= 8 {
        out.push_str(open);
        for (k, item) in items.iter().enumerate() {
            if k > 0 {
                out.push_str(", ");
            }
            item.write(out, depth);
        }
        if items.len() == 1 && open == "(" {
            // `(x)` would be read as x itself, not a tuple of one.
            out.push(',');
        }
        out.push_str(close);
        return;
    }
    out.push_str(open);
    out.push('\n');
    for item in items {
        indent(out, depth + 1);
        item.write(out, depth + 1);
        out.push_str(",\n");
    }
    indent(out, depth);
    out.push_str(close);
}

/// `value` in the shape of `old`, the value it replaces: an integer where a
/// float was stays a float, a string where a name was is a name (or, where
/// a compound value was, RON text), a list where a tuple was a tuple, a
/// dict where a struct was that struct.
/// A value for a struct field not yet written: a dict is a struct, as the
/// scene's optional fields that hold several values are (`analysis.settle`,
/// `analysis.damping`); anything else as [`shape`] makes it.
fn shape_new(value: &Given) -> Node {
    match value {
        Given::Dict(entries) => Node::Struct(
            String::new(),
            (entries.iter())
                .map(|(k, v)| (k.clone(), shape_new(v)))
                .collect(),
        ),
        _ => shape(value, None),
    }
}

pub fn shape(value: &Given, old: Option<&Node>) -> Node {
    // Options and newtype structs wrap what the value really replaces.
    match old {
        Some(Node::Some(inner)) => return shape(value, Some(inner)),
        Some(Node::Wrapped(name, inner)) => {
            return Node::Wrapped(name.clone(), Box::new(shape(value, Some(inner))));
        }
        Some(Node::Newtype(name, inner)) if !matches!(value, Given::Dict(_)) => {
            if let Given::Str(text) = value {
                if !matches!(inner.as_ref(), Node::Str(_)) {
                    return Node::Raw(text.clone());
                }
            }
            return Node::Newtype(name.clone(), Box::new(shape(value, Some(inner))));
        }
        _ => {}
    }
    match value {
        Given::None => Node::None,
        Given::Bool(b) => Node::Bool(*b),
        Given::Int(i) => match old {
            Some(Node::Float(_)) => Node::Float(*i as f64),
            _ => Node::Int(*i),
        },
        Given::Float(x) => Node::Float(*x),
        Given::Str(s) => match old {
            Some(Node::Name(_)) => Node::Name(s.clone()),
            Some(
                Node::Struct(..) | Node::Tuple(..) | Node::Seq(_) | Node::Map(_) | Node::Raw(_),
            ) => Node::Raw(s.clone()),
            _ => Node::Str(s.clone()),
        },
        Given::List(items) => {
            let like = |k: usize| match old {
                Some(Node::Seq(v)) | Some(Node::Tuple(_, v)) => v.get(k).or(v.first()),
                _ => None,
            };
            let nodes = items
                .iter()
                .enumerate()
                .map(|(k, v)| shape(v, like(k)))
                .collect();
            match old {
                Some(Node::Tuple(name, _)) => Node::Tuple(name.clone(), nodes),
                _ => Node::Seq(nodes),
            }
        }
        Given::Dict(entries) => match old {
            Some(Node::Newtype(name, inner)) => {
                Node::Newtype(name.clone(), Box::new(shape(value, Some(inner))))
            }
            Some(Node::Struct(name, fields)) => Node::Struct(
                name.clone(),
                entries
                    .iter()
                    .map(|(k, v)| {
                        let was = fields.iter().find(|(f, _)| f == k).map(|(_, n)| n);
                        (k.clone(), shape(v, was))
                    })
                    .collect(),
            ),
            Some(Node::Map(old_entries)) => Node::Map(
                entries
                    .iter()
                    .map(|(k, v)| {
                        let was = old_entries
                            .iter()
                            .find(|(key, _)| key.key_text() == *k)
                            .or(old_entries.first())
                            .map(|(_, n)| n);
                        (Node::Str(k.clone()), shape(v, was))
                    })
                    .collect(),
            ),
            _ => Node::Map(
                entries
                    .iter()
                    .map(|(k, v)| (Node::Str(k.clone()), shape(v, None)))
                    .collect(),
            ),
        },
    }
}

/// Builds a [`Node`] from any `Serialize` value.
struct TreeSerializer;

#[derive(Debug)]
struct Never(String);

impl std::fmt::Display for Never {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Never {}

impl ser::Error for Never {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        Never(msg.to_string())
    }
}

/// A sequence, tuple or struct being built.
struct Compound {
    name: Option<String>,
    kind: Kind,
    items: Vec<Node>,
    fields: Vec<(String, Node)>,
    entries: Vec<(Node, Node)>,
    key: Option<Node>,
}

/// Tuple structs and tuple variants are named tuples; struct variants are
/// named structs, written alike.
enum Kind {
    Seq,
    Tuple,
    Struct,
    Map,
}

impl Compound {
    fn new(name: Option<&str>, kind: Kind) -> Self {
        Compound {
            name: name.map(str::to_string),
            kind,
            items: Vec::new(),
            fields: Vec::new(),
            entries: Vec::new(),
            key: None,
        }
    }

    fn finish(self) -> Node {
        match self.kind {
            Kind::Seq => Node::Seq(self.items),
            Kind::Tuple => Node::Tuple(self.name, self.items),
            Kind::Struct => Node::Struct(self.name.unwrap_or_default(), self.fields),
            Kind::Map => Node::Map(self.entries),
        }
    }
}

impl ser::Serializer for TreeSerializer {
    type Ok = Node;
    type Error = Never;
    type SerializeSeq = Compound;
    type SerializeTuple = Compound;
    type SerializeTupleStruct = Compound;
    type SerializeTupleVariant = Compound;
    type SerializeMap = Compound;
    type SerializeStruct = Compound;
    type SerializeStructVariant = Compound;

    fn serialize_bool(self, v: bool) -> Result<Node, Never> {
        Ok(Node::Bool(v))
    }
    fn serialize_i8(self, v: i8) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_i16(self, v: i16) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_i32(self, v: i32) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_i64(self, v: i64) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_i128(self, v: i128) -> Result<Node, Never> {
        Ok(Node::Int(v))
    }
    fn serialize_u8(self, v: u8) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_u16(self, v: u16) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_u32(self, v: u32) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_u64(self, v: u64) -> Result<Node, Never> {
        Ok(Node::Int(v.into()))
    }
    fn serialize_f32(self, v: f32) -> Result<Node, Never> {
        Ok(Node::Float(v.into()))
    }
    fn serialize_f64(self, v: f64) -> Result<Node, Never> {
        Ok(Node::Float(v))
    }
    fn serialize_char(self, v: char) -> Result<Node, Never> {
        Ok(Node::Char(v))
    }
    fn serialize_str(self, v: &str) -> Result<Node, Never> {
        Ok(Node::Str(v.to_string()))
    }
    fn serialize_bytes(self, v: &[u8]) -> Result<Node, Never> {
        Ok(Node::Seq(
            v.iter().map(|b| Node::Int((*b).into())).collect(),
        ))
    }
    fn serialize_none(self) -> Result<Node, Never> {
        Ok(Node::None)
    }
    fn serialize_some<T: ?Sized + Serialize>(self, value: &T) -> Result<Node, Never> {
        Ok(Node::Some(Box::new(value.serialize(TreeSerializer)?)))
    }
    fn serialize_unit(self) -> Result<Node, Never> {
        Ok(Node::Unit)
    }
    fn serialize_unit_struct(self, name: &'static str) -> Result<Node, Never> {
        Ok(Node::Name(name.to_string()))
    }
    fn serialize_unit_variant(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
    ) -> Result<Node, Never> {
        Ok(Node::Name(variant.to_string()))
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        name: &'static str,
        value: &T,
    ) -> Result<Node, Never> {
        Ok(Node::Wrapped(
            name.to_string(),
            Box::new(value.serialize(TreeSerializer)?),
        ))
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
        value: &T,
    ) -> Result<Node, Never> {
        Ok(Node::Newtype(
            variant.to_string(),
            Box::new(value.serialize(TreeSerializer)?),
        ))
    }
    fn serialize_seq(self, _len: Option<usize>) -> Result<Compound, Never> {
        Ok(Compound::new(None, Kind::Seq))
    }
    fn serialize_tuple(self, _len: usize) -> Result<Compound, Never> {
        Ok(Compound::new(None, Kind::Tuple))
    }
    fn serialize_tuple_struct(self, name: &'static str, _len: usize) -> Result<Compound, Never> {
        Ok(Compound::new(Some(name), Kind::Tuple))
    }
    fn serialize_tuple_variant(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
        _len: usize,
    ) -> Result<Compound, Never> {
        Ok(Compound::new(Some(variant), Kind::Tuple))
    }
    fn serialize_map(self, _len: Option<usize>) -> Result<Compound, Never> {
        Ok(Compound::new(None, Kind::Map))
    }
    fn serialize_struct(self, name: &'static str, _len: usize) -> Result<Compound, Never> {
        Ok(Compound::new(Some(name), Kind::Struct))
    }
    fn serialize_struct_variant(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
        _len: usize,
    ) -> Result<Compound, Never> {
        Ok(Compound::new(Some(variant), Kind::Struct))
    }
}

impl ser::SerializeSeq for Compound {
    type Ok = Node;
    type Error = Never;
    fn serialize_element<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), Never> {
        self.items.push(value.serialize(TreeSerializer)?);
        Ok(())
    }
    fn end(self) -> Result<Node, Never> {
        Ok(self.finish())
    }
}

impl ser::SerializeTuple for Compound {
    type Ok = Node;
    type Error = Never;
    fn serialize_element<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), Never> {
        ser::SerializeSeq::serialize_element(self, value)
    }
    fn end(self) -> Result<Node, Never> {
        Ok(self.finish())
    }
}

impl ser::SerializeTupleStruct for Compound {
    type Ok = Node;
    type Error = Never;
    fn serialize_field<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), Never> {
        ser::SerializeSeq::serialize_element(self, value)
    }
    fn end(self) -> Result<Node, Never> {
        Ok(self.finish())
    }
}

impl ser::SerializeTupleVariant for Compound {
    type Ok = Node;
    type Error = Never;
    fn serialize_field<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), Never> {
        ser::SerializeSeq::serialize_element(self, value)
    }
    fn end(self) -> Result<Node, Never> {
        Ok(self.finish())
    }
}

impl ser::SerializeMap for Compound {
    type Ok = Node;
    type Error = Never;
    fn serialize_key<T: ?Sized + Serialize>(&mut self, key: &T) -> Result<(), Never> {
        self.key = Some(key.serialize(TreeSerializer)?);
        Ok(())
    }
    fn serialize_value<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), Never> {
        let key = self.key.take().unwrap_or(Node::Unit);
        self.entries.push((key, value.serialize(TreeSerializer)?));
        Ok(())
    }
    fn end(self) -> Result<Node, Never> {
        Ok(self.finish())
    }
}

impl ser::SerializeStruct for Compound {
    type Ok = Node;
    type Error = Never;
    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), Never> {
        self.fields
            .push((key.to_string(), value.serialize(TreeSerializer)?));
        Ok(())
    }
    fn end(self) -> Result<Node, Never> {
        Ok(self.finish())
    }
}

impl ser::SerializeStructVariant for Compound {
    type Ok = Node;
    type Error = Never;
    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), Never> {
        ser::SerializeStruct::serialize_field(self, key, value)
    }
    fn end(self) -> Result<Node, Never> {
        Ok(self.finish())
    }
}
