//! Finds where a value sits in scene text (`blocks[3]`, `analysis.dt`,
//! `materials["rock"]`) so semantic errors can give a line and column.
//!
//! A tolerant scanner, not a parser: the text has already parsed, so it only
//! needs to skip strings and comments and balance brackets.

/// One step of a path into the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Seg<'a> {
    /// A struct field (or a variant's field) by name.
    Field(&'a str),
    /// An element of a list or tuple.
    Index(usize),
    /// A map entry by its string key.
    Key(&'a str),
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Open(char),
    Close,
    Comma,
    Colon,
    Ident(String),
    Str(String),
    Other,
}

#[derive(Debug, Clone)]
struct Tok {
    kind: Kind,
    line: usize,
    col: usize,
}

/// Line and column (1-based) of the value at `path`, or of the deepest part
/// of it that can be found; `None` if not even the first step is found.
pub fn locate(text: &str, path: &[Seg<'_>]) -> Option<(usize, usize)> {
    locate_steps(text, path).0
}

/// Line and column of the value at `path` if every step of it is written.
pub fn locate_exact(text: &str, path: &[Seg<'_>]) -> Option<(usize, usize)> {
    match locate_steps(text, path) {
        (found, steps) if steps == path.len() => found,
        _ => None,
    }
}

/// The deepest place found and how many steps of `path` reach it.
fn locate_steps(text: &str, path: &[Seg<'_>]) -> (Option<(usize, usize)>, usize) {
    let toks = tokenize(text);
    let mut i = 0;
    // Skip `#![enable(...)]` attributes.
    while matches!(
        toks.get(i),
        Some(Tok {
            kind: Kind::Other,
            ..
        })
    ) {
        i += 1;
        if matches!(
            toks.get(i),
            Some(Tok {
                kind: Kind::Open('['),
                ..
            })
        ) {
            i = skip_value(&toks, i);
        }
    }
    let mut found = None;
    let mut steps = 0;
    for seg in path {
        match find(&toks, i, *seg) {
            Some((at, value)) => {
                found = Some((toks[at].line, toks[at].col));
                i = value;
                steps += 1;
            }
            None => break,
        }
    }
    (found, steps)
}

/// Finds `seg` inside the value starting at token `i`: the token to report
/// and the start of the inner value.
fn find(toks: &[Tok], mut i: usize, seg: Seg<'_>) -> Option<(usize, usize)> {
    // A struct or variant name before the bracket.
    if matches!(toks.get(i)?.kind, Kind::Ident(_)) {
        i += 1;
    }
    let Kind::Open(bracket) = toks.get(i)?.kind else {
        return None;
    };
    let mut j = i + 1;
    let mut index = 0;
    loop {
        let tok = toks.get(j)?;
        if tok.kind == Kind::Close {
            return None;
        }
        match (seg, bracket) {
            (Seg::Field(name), '(') => {
                if toks.get(j + 1).map(|t| &t.kind) == Some(&Kind::Colon) {
                    if tok.kind == Kind::Ident(name.to_string()) {
                        return Some((j, j + 2));
                    }
                    j += 2;
                }
            }
            (Seg::Key(key), '{') => {
                let start = j;
                j = skip_value(toks, j);
                if toks.get(j)?.kind != Kind::Colon {
                    return None;
                }
                if tok.kind == Kind::Str(key.to_string()) {
                    return Some((start, j + 1));
                }
                j += 1;
            }
            (Seg::Index(k), '[' | '(') => {
                if index == k {
                    return Some((j, j));
                }
                index += 1;
            }
            _ => return None,
        }
        j = skip_value(toks, j);
        match toks.get(j)?.kind {
            Kind::Comma => j += 1,
            _ => return None,
        }
    }
}

/// Index of the comma or closing bracket that ends the value at `i`.
fn skip_value(toks: &[Tok], mut i: usize) -> usize {
    let mut depth = 0usize;
    while let Some(t) = toks.get(i) {
        match t.kind {
            Kind::Open(_) => depth += 1,
            Kind::Close => {
                if depth == 0 {
                    return i;
                }
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            Kind::Comma | Kind::Colon if depth == 0 => return i,
            _ => {}
        }
        i += 1;
    }
    i
}

fn tokenize(text: &str) -> Vec<Tok> {
    let chars: Vec<char> = text.chars().collect();
    let mut toks = Vec::new();
    let (mut i, mut line, mut col) = (0, 1, 1);
    // Moves past `n` characters, keeping line and column.
    let advance = |i: &mut usize, line: &mut usize, col: &mut usize, n: usize| {
        for _ in 0..n {
            if *i >= chars.len() {
                return;
            }
            if chars[*i] == '\n' {
                *line += 1;
                *col = 1;
            } else {
                *col += 1;
            }
            *i += 1;
        }
    };
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        let (l0, c0) = (line, col);
        let kind = if c.is_whitespace() {
            advance(&mut i, &mut line, &mut col, 1);
            continue;
        } else if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                advance(&mut i, &mut line, &mut col, 1);
            }
            continue;
        } else if c == '/' && next == Some('*') {
            // RON block comments nest.
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    advance(&mut i, &mut line, &mut col, 2);
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    advance(&mut i, &mut line, &mut col, 2);
                    if depth == 0 {
                        break;
                    }
                } else {
                    advance(&mut i, &mut line, &mut col, 1);
                }
            }
            continue;
        } else if c == '"' {
            let mut s = String::new();
            advance(&mut i, &mut line, &mut col, 1);
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    s.push(chars[i]);
                    advance(&mut i, &mut line, &mut col, 1);
                }
                if i < chars.len() {
                    s.push(chars[i]);
                }
                advance(&mut i, &mut line, &mut col, 1);
            }
            advance(&mut i, &mut line, &mut col, 1);
            Kind::Str(s)
        } else if c == 'r' && matches!(next, Some('"' | '#')) && raw_string_start(&chars, i) {
            let hashes = chars[i + 1..].iter().take_while(|&&h| h == '#').count();
            advance(&mut i, &mut line, &mut col, 2 + hashes);
            let mut s = String::new();
            while i < chars.len() {
                if chars[i] == '"'
                    && chars[i + 1..]
                        .iter()
                        .take(hashes)
                        .filter(|&&h| h == '#')
                        .count()
                        == hashes
                {
                    advance(&mut i, &mut line, &mut col, 1 + hashes);
                    break;
                }
                s.push(chars[i]);
                advance(&mut i, &mut line, &mut col, 1);
            }
            Kind::Str(s)
        } else if matches!(c, '(' | '[' | '{') {
            advance(&mut i, &mut line, &mut col, 1);
            Kind::Open(c)
        } else if matches!(c, ')' | ']' | '}') {
            advance(&mut i, &mut line, &mut col, 1);
            Kind::Close
        } else if c == ',' {
            advance(&mut i, &mut line, &mut col, 1);
            Kind::Comma
        } else if c == ':' {
            advance(&mut i, &mut line, &mut col, 1);
            Kind::Colon
        } else if c.is_alphabetic() || c == '_' {
            let mut s = String::new();
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                s.push(chars[i]);
                advance(&mut i, &mut line, &mut col, 1);
            }
            Kind::Ident(s)
        } else {
            // Numbers, signs, `#`, chars: only their extent matters.
            while i < chars.len() && !is_break(chars[i]) {
                advance(&mut i, &mut line, &mut col, 1);
            }
            if (l0, c0) == (line, col) {
                advance(&mut i, &mut line, &mut col, 1);
            }
            Kind::Other
        };
        toks.push(Tok {
            kind,
            line: l0,
            col: c0,
        });
    }
    toks
}

fn is_break(c: char) -> bool {
    c.is_whitespace() || matches!(c, '(' | ')' | '[' | ']' | '{' | '}' | ',' | ':' | '"' | '/')
}

/// `r"..."` or `r#"..."#`, as opposed to an identifier starting with r.
fn raw_string_start(chars: &[char], i: usize) -> bool {
    let hashes = chars[i + 1..].iter().take_while(|&&h| h == '#').count();
    chars.get(i + 1 + hashes) == Some(&'"')
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"// a scene
#![enable(implicit_some)]
Scene(
    analysis: (duration: 1.0, /* dt: 3, */ dt: 0.5),
    materials: { "a, b": (density: 1.0), "rock": (young: 2.0) },
    blocks: [
        Polygon(material: "x(", vertices: [(0, 0), (1, 0), (1, 1)]),
        // blocks: [ Rectangle ]
        Rectangle(center: (0, 0), width: 1, height: 2),
    ],
)
"#;

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
        use Seg::*;
        assert_eq!(locate(TEXT, &[Field("analysis"), Field("dt")]), at(4, "dt"));
        assert_eq!(locate(TEXT, &[Field("blocks"), Index(0)]), at(7, "Polygon"));
        assert_eq!(
            locate(TEXT, &[Field("blocks"), Index(1)]),
            at(9, "Rectangle")
        );
        assert_eq!(
            locate(TEXT, &[Field("blocks"), Index(1), Field("width")]),
            at(9, "width")
        );
        assert_eq!(
            locate(
                TEXT,
                &[Field("blocks"), Index(0), Field("vertices"), Index(2)]
            ),
            at(7, "(1, 1)")
        );
        assert_eq!(
            locate(TEXT, &[Field("materials"), Key("rock")]),
            at(5, "\"rock\"")
        );
        assert_eq!(
            locate(TEXT, &[Field("materials"), Key("rock"), Field("young")]),
            at(5, "young")
        );
        // Missing parts fall back to the deepest found.
        assert_eq!(locate(TEXT, &[Field("blocks"), Index(5)]), at(6, "blocks"));
        assert_eq!(locate(TEXT, &[Field("loads"), Index(0)]), None);
        // Exactly: only when every step is written.
        assert_eq!(
            locate_exact(TEXT, &[Field("analysis"), Field("dt")]),
            at(4, "dt")
        );
        assert_eq!(
            locate_exact(TEXT, &[Field("analysis"), Field("plane")]),
            None
        );
        assert_eq!(locate_exact(TEXT, &[Field("blocks"), Index(5)]), None);
    }
}
