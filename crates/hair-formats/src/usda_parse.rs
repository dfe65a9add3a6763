//! The parser of USD's text format (`.usda`), the one every text layer goes through: the layer's
//! metadata (`upAxis`, `metersPerUnit`), prims nested to any depth, and in every prim of the kind
//! asked for ([`PrimKind`]) the attributes it reads (`usda_prims.rs`): in `def BasisCurves`
//! `type`, `basis`, `wrap`, `curveVertexCounts`, `points`, `widths`, `primvars:widths` and
//! `primvars:displayColor` (with their `:indices` and `interpolation`); in `def Mesh` `points`,
//! `faceVertexCounts`, `faceVertexIndices` and `orientation`; each as a default value and/or
//! `.timeSamples`, resolved at a time while parsing (`usda_values.rs`). Everything else (other
//! prims, relationships, variant sets, dictionaries, connections) is skipped by its brackets, on
//! an explicit stack (no recursion but into prims, at most [`MAX_PRIM_DEPTH`] deep); composition
//! arcs (references, payloads, sublayers) are not followed. When meshes are read, the
//! `xformOpOrder` and `xformOp:` attributes of every `def` prim are collected too
//! ([`XformPrim`]), for the mesh readers to apply; a sequence read
//! ([`parse_layer_sequence`]) keeps every time sample of what it reads.

use glam::Vec3;

use super::error::FormatErrorKind;
use super::options::UpAxis;
use super::text::shorten;
use super::usda_lex::{Kind, Lexer, Token, unexpected};
use super::usda_prims::{Collected, Field, Layer, PrimKind, Slot, XformPrim};
use super::usda_values::{Array, Attr, Authored, Sample};

#[path = "usda_parse_xform.rs"]
mod xform;

/// Deepest prim nesting read (deeper is refused rather than risking the stack).
const MAX_PRIM_DEPTH: usize = 200;

/// Parses `text` (USD text, UTF-8) into its layer and its prims of `kind`, resolving values at
/// `time`.
pub(crate) fn parse_layer(
    text: &str,
    time: Option<f64>,
    kind: PrimKind,
) -> Result<Layer, FormatErrorKind> {
    parse(text, time, kind, false)
}

/// Parses `text` into its layer and its prims of `kind` with every time sample of their
/// attributes ([`Attr::samples`](super::usda_values::Attr)), and the transform ops of every
/// `def` prim ([`Layer::xforms`]).
pub(crate) fn parse_layer_sequence(text: &str, kind: PrimKind) -> Result<Layer, FormatErrorKind> {
    parse(text, None, kind, true)
}

fn parse(
    text: &str,
    time: Option<f64>,
    kind: PrimKind,
    sequence: bool,
) -> Result<Layer, FormatErrorKind> {
    let mut parser = Parser {
        lexer: Lexer::new(text),
        time,
        sequence,
        xforms: kind == PrimKind::Mesh,
        kind,
        path: Vec::new(),
        prims_seen: 0,
        layer: Layer {
            up: UpAxis::Y,
            meters_per_unit: 0.01,
            meters_per_unit_line: 1,
            curves: Vec::new(),
            meshes: Vec::new(),
            time_codes_per_second: None,
            frames_per_second: None,
            xforms: Vec::new(),
        },
    };
    if parser.lexer.peek()?.is_some_and(|t| t.is(b'(')) {
        parser.layer_metadata()?;
    }
    while let Some(token) = parser.lexer.next_token()? {
        match token.text {
            "def" | "over" | "class" if token.kind == Kind::Ident => parser.prim(token, 0)?,
            _ if token.is(b';') => {}
            _ => return Err(unexpected(&token, "a prim (`def`, `over` or `class`)")),
        }
    }
    // Namespace order, as USD walks a layer: a parent before its children.
    parser.layer.meshes.sort_by_key(|mesh| mesh.order);
    Ok(parser.layer)
}

struct Parser<'a> {
    lexer: Lexer<'a>,
    time: Option<f64>,
    /// Whether every time sample is kept (a sequence is read).
    sequence: bool,
    /// Whether the transform ops of every `def` prim are collected (meshes are read).
    xforms: bool,
    /// The prims collected.
    kind: PrimKind,
    /// The names of the prims the parser is inside, outermost first.
    path: Vec<String>,
    /// Prims begun so far (each prim's place in namespace order).
    prims_seen: usize,
    layer: Layer,
}

/// A number in `token` (a number, or `inf` / `nan` written as a name).
fn number<T: std::str::FromStr>(token: &Token, what: &str) -> Result<T, FormatErrorKind> {
    let parsed = match token.kind {
        Kind::Number | Kind::Ident => token.text.parse().ok(),
        _ => None,
    };
    parsed.ok_or_else(|| FormatErrorKind::Syntax {
        line: token.line,
        message: format!("{what}: expected a number, found {}", token.shown()),
    })
}

/// The contents of a string token without its quotes.
fn unquote<'t>(token: &Token<'t>) -> &'t str {
    let text = token.text;
    let quotes = if text.starts_with("\"\"\"") || text.starts_with("'''") {
        3
    } else {
        1
    };
    text.get(quotes..text.len().saturating_sub(quotes))
        .unwrap_or_default()
}

impl<'a> Parser<'a> {
    fn ident(&mut self, what: &str) -> Result<Token<'a>, FormatErrorKind> {
        let token = self.lexer.expect_any(what)?;
        if token.kind == Kind::Ident {
            Ok(token)
        } else {
            Err(unexpected(&token, what))
        }
    }

    /// Skips one value: a single token, or everything to the bracket that closes the first.
    fn skip_value(&mut self) -> Result<(), FormatErrorKind> {
        let first = self.lexer.expect_any("a value")?;
        let closer = |t: &Token| match t.kind {
            Kind::Punct(b'(') => Some(b')'),
            Kind::Punct(b'[') => Some(b']'),
            Kind::Punct(b'{') => Some(b'}'),
            _ => None,
        };
        let Some(close) = closer(&first) else {
            return match first.kind {
                Kind::Punct(_) => Err(unexpected(&first, "a value")),
                Kind::Asset => {
                    // A reference: `@file.usda@</prim>`.
                    if self.lexer.peek()?.is_some_and(|t| t.kind == Kind::Path) {
                        self.lexer.next_token()?;
                    }
                    Ok(())
                }
                _ => Ok(()),
            };
        };
        let mut open = vec![(close, first.line)];
        while let Some(&(close, line)) = open.last() {
            let token = self.lexer.expect_any(&format!(
                "`{}` closing the bracket of line {line}",
                close as char
            ))?;
            if let Some(inner) = closer(&token) {
                open.push((inner, token.line));
            } else if token.is(close) {
                open.pop();
            } else if matches!(token.kind, Kind::Punct(b')' | b']' | b'}')) {
                return Err(unexpected(
                    &token,
                    &format!("`{}` closing the bracket of line {line}", close as char),
                ));
            }
        }
        Ok(())
    }

    /// A metadata block `( … )`: returns the atoms of the `wanted` entries, skips the rest.
    fn metadata(
        &mut self,
        wanted: &[&str],
    ) -> Result<Vec<(Token<'a>, Token<'a>)>, FormatErrorKind> {
        self.lexer.expect(b'(', "opening metadata")?;
        let mut found = Vec::new();
        loop {
            let token = self.lexer.expect_any("metadata or `)`")?;
            match token.kind {
                Kind::Punct(b')') => return Ok(found),
                Kind::Punct(b';') | Kind::String => {}
                Kind::Ident => {
                    let mut name = token;
                    if matches!(
                        name.text,
                        "add" | "prepend" | "append" | "delete" | "reorder"
                    ) && self.lexer.peek()?.is_some_and(|t| t.kind == Kind::Ident)
                    {
                        name = self.ident("a metadata name")?;
                    }
                    self.lexer
                        .expect(b'=', &format!("after metadata `{}`", shorten(name.text)))?;
                    if wanted.contains(&name.text) {
                        let value = self.lexer.expect_any("a metadata value")?;
                        if !matches!(value.kind, Kind::String | Kind::Number | Kind::Ident) {
                            return Err(unexpected(
                                &value,
                                &format!("a single value for `{}`", name.text),
                            ));
                        }
                        found.push((name, value));
                    } else {
                        self.skip_value()?;
                    }
                }
                _ => return Err(unexpected(&token, "a metadata name or `)`")),
            }
        }
    }

    fn layer_metadata(&mut self) -> Result<(), FormatErrorKind> {
        let wanted = [
            "upAxis",
            "metersPerUnit",
            "timeCodesPerSecond",
            "framesPerSecond",
        ];
        for (name, value) in self.metadata(&wanted)? {
            if matches!(name.text, "timeCodesPerSecond" | "framesPerSecond") {
                let rate: f64 = number(&value, name.text)?;
                if !(rate.is_finite() && rate > 0.0) {
                    return Err(FormatErrorKind::Syntax {
                        line: value.line,
                        message: format!(
                            "{} {} is invalid (allowed: a finite number > 0)",
                            name.text,
                            value.shown()
                        ),
                    });
                }
                if name.text == "timeCodesPerSecond" {
                    self.layer.time_codes_per_second = Some(rate);
                } else {
                    self.layer.frames_per_second = Some(rate);
                }
            } else if name.text == "upAxis" {
                self.layer.up = match (value.kind, unquote(&value)) {
                    (Kind::String, "Y") => UpAxis::Y,
                    (Kind::String, "Z") => UpAxis::Z,
                    _ => {
                        return Err(FormatErrorKind::Syntax {
                            line: value.line,
                            message: format!(
                                "upAxis {} is not supported (allowed: \"Y\" or \"Z\")",
                                value.shown()
                            ),
                        });
                    }
                };
            } else {
                let meters: f64 = number(&value, "metersPerUnit")?;
                if !(meters.is_finite() && meters > 0.0 && (meters as f32) > 0.0) {
                    return Err(FormatErrorKind::Syntax {
                        line: value.line,
                        message: format!(
                            "metersPerUnit {} is invalid (allowed: a finite number > 0)",
                            value.shown()
                        ),
                    });
                }
                self.layer.meters_per_unit = meters;
                self.layer.meters_per_unit_line = value.line;
            }
        }
        Ok(())
    }

    /// A prim from its specifier (`def`, `over`, `class`) to its closing `}`.
    fn prim(&mut self, specifier: Token<'a>, depth: usize) -> Result<(), FormatErrorKind> {
        if depth >= MAX_PRIM_DEPTH {
            return Err(FormatErrorKind::Syntax {
                line: specifier.line,
                message: format!("prims nested deeper than {MAX_PRIM_DEPTH} levels"),
            });
        }
        let mut token = self.lexer.expect_any("a prim type or name")?;
        let mut type_name = None;
        if token.kind == Kind::Ident {
            type_name = Some(token.text);
            token = self.lexer.expect_any("the prim's name")?;
        }
        if token.kind != Kind::String {
            return Err(unexpected(&token, "the prim's name in quotes"));
        }
        let name = token;
        if self.lexer.peek()?.is_some_and(|t| t.is(b'(')) {
            self.metadata(&[])?;
        }
        self.lexer.expect(b'{', "opening the prim's body")?;
        self.path.push(unquote(&name).to_owned());
        let order = self.prims_seen;
        self.prims_seen += 1;
        let mut collected = (specifier.text == "def" && type_name == Some(self.kind.type_name()))
            .then(|| {
                let path = format!("/{}", self.path.join("/"));
                Collected::new(self.kind, shorten(name.text), path, name.line, order)
            });
        let mut xform = (self.xforms && specifier.text == "def").then(|| XformPrim {
            path: format!("/{}", self.path.join("/")),
            line: name.line,
            order: None,
            ops: Vec::new(),
        });
        loop {
            let token = self.lexer.expect_any(&format!(
                "a property, a child prim or `}}` closing prim {} of line {}",
                shorten(name.text),
                name.line
            ))?;
            match (token.kind, token.text) {
                (Kind::Punct(b'}'), _) => break,
                (Kind::Punct(b';'), _) => {}
                (Kind::Ident, "def" | "over" | "class") => self.prim(token, depth + 1)?,
                (Kind::Ident, "variantSet") => {
                    self.lexer.expect_any("the variant set's name")?;
                    self.lexer.expect(b'=', "after the variant set's name")?;
                    self.skip_value()?;
                }
                (Kind::Ident, "reorder") => {
                    self.ident("`nameChildren` or `properties`")?;
                    self.lexer.expect(b'=', "after `reorder …`")?;
                    self.skip_value()?;
                }
                (Kind::Ident, _) => self.property(token, collected.as_mut(), xform.as_mut())?,
                _ => return Err(unexpected(&token, "a property, a child prim or `}`")),
            }
        }
        self.path.pop();
        match collected {
            Some(Collected::Curves(curves)) => self.layer.curves.push(*curves),
            Some(Collected::Mesh(mesh)) => self.layer.meshes.push(*mesh),
            None => {}
        }
        if let Some(xform) = xform
            && xform.order.is_some()
        {
            self.layer.xforms.push(xform);
        }
        Ok(())
    }

    /// A property from its first word to the end of its value and metadata.
    fn property(
        &mut self,
        first: Token<'a>,
        collected: Option<&mut Collected>,
        xform: Option<&mut XformPrim>,
    ) -> Result<(), FormatErrorKind> {
        let mut token = first;
        while matches!(
            token.text,
            "custom" | "uniform" | "varying" | "config" | "prepend" | "append" | "add" | "delete"
        ) {
            token = self.ident("a property type")?;
        }
        if token.text == "rel" {
            self.ident("the relationship's name")?;
            if self.lexer.eat(b'=')? {
                self.skip_value()?;
            }
            return self.optional_metadata(&[]).map(drop);
        }
        let type_token = token;
        let mut type_name = type_token.text.to_owned();
        if self.lexer.eat(b'[')? {
            self.lexer.expect(b']', "closing the array type `[]`")?;
            type_name.push_str("[]");
        }
        let name = self.ident("the attribute's name")?;
        let (base, suffix) = match name.text.split_once('.') {
            Some((base, suffix)) => (base, Some(suffix)),
            None => (name.text, None),
        };
        if let Some(xform) = xform
            && (base == "xformOpOrder" || base.starts_with("xformOp:"))
        {
            return self.xform_property(xform, &type_name, &type_token, base, suffix, name.line);
        }
        let field = collected
            .as_ref()
            .and_then(|prim| Field::from_name(prim.kind(), base));
        let Some((field, prim)) = field.zip(collected) else {
            return self.skip_property();
        };
        let (fits, expected) = field.accepts(&type_name);
        if !fits {
            return Err(FormatErrorKind::Syntax {
                line: type_token.line,
                message: format!(
                    "`{base}` of {} {} has type `{}`; expected `{expected}`",
                    prim.kind().type_name(),
                    prim.shown(),
                    shorten(&type_name)
                ),
            });
        }
        let line = name.line;
        let time = self.time;
        match prim.slot(field) {
            Some(Slot::Token(slot)) => self.attribute(slot, line, suffix, time, Self::token),
            Some(Slot::Ints(slot)) => self.attribute(slot, line, suffix, time, Self::ints),
            Some(Slot::Floats(slot)) => self.attribute(slot, line, suffix, time, Self::floats),
            Some(Slot::Vec3s(slot)) => self.attribute(slot, line, suffix, time, Self::vec3s),
            None => self.skip_property(),
        }
    }

    /// The rest of a property that is not read: its value, if any, and its metadata.
    fn skip_property(&mut self) -> Result<(), FormatErrorKind> {
        if self.lexer.eat(b'=')? {
            self.skip_value()?;
        }
        self.optional_metadata(&[]).map(drop)
    }

    /// Metadata after a property, if any; returns the `wanted` entries.
    fn optional_metadata(
        &mut self,
        wanted: &[&str],
    ) -> Result<Vec<(Token<'a>, Token<'a>)>, FormatErrorKind> {
        if self.lexer.peek()?.is_some_and(|t| t.is(b'(')) {
            self.metadata(wanted)
        } else {
            Ok(Vec::new())
        }
    }

    /// The value (`= …` or `.timeSamples = { … }`) and metadata of an attribute that is read.
    fn attribute<T: Sample>(
        &mut self,
        slot: &mut Option<Attr<T>>,
        line: usize,
        suffix: Option<&str>,
        time: Option<f64>,
        value: fn(&mut Self) -> Result<Authored<T>, FormatErrorKind>,
    ) -> Result<(), FormatErrorKind> {
        let attr = slot.get_or_insert_with(|| Attr::new(line));
        let sequence = self.sequence;
        let assigned = self.lexer.eat(b'=')?;
        match (suffix, assigned) {
            (_, false) => {}
            (None | Some("default"), true) => attr.default = Some(value(self)?),
            (Some("timeSamples"), true) => {
                self.lexer.expect(b'{', "opening the time samples")?;
                loop {
                    if self.lexer.eat(b'}')? {
                        break;
                    }
                    let token = self.lexer.expect_any("a time code")?;
                    let t: f64 = number(&token, "time code")?;
                    if !t.is_finite() {
                        return Err(FormatErrorKind::Syntax {
                            line: token.line,
                            message: format!("time code {} is not finite", token.shown()),
                        });
                    }
                    self.lexer.expect(b':', "after the time code")?;
                    let sample = value(self)?;
                    if sequence {
                        attr.samples.push((t, sample));
                    } else {
                        attr.offer(time, t, sample);
                    }
                    if !self.lexer.eat(b',')? {
                        self.lexer.expect(b'}', "closing the time samples")?;
                        break;
                    }
                }
            }
            (Some(_), true) => self.skip_value()?,
        }
        for (_, value) in self.optional_metadata(&["interpolation"])? {
            attr.interpolation = Some((unquote(&value).to_owned(), value.line));
        }
        Ok(())
    }

    /// `None` (a blocked value) if that is next.
    fn blocked(&mut self) -> Result<bool, FormatErrorKind> {
        if self
            .lexer
            .peek()?
            .is_some_and(|t| t.kind == Kind::Ident && t.text == "None")
        {
            self.lexer.next_token()?;
            return Ok(true);
        }
        Ok(false)
    }

    fn token(&mut self) -> Result<Authored<String>, FormatErrorKind> {
        if self.blocked()? {
            return Ok(None);
        }
        let token = self.lexer.expect_any("a token in quotes")?;
        if token.kind != Kind::String {
            return Err(unexpected(&token, "a token in quotes"));
        }
        Ok(Some(unquote(&token).to_owned()))
    }

    /// `[a, b, …]` (a trailing comma allowed), each element read by `element`.
    fn array<T>(
        &mut self,
        mut element: impl FnMut(&mut Self, &mut Array<T>) -> Result<(), FormatErrorKind>,
    ) -> Result<Authored<Array<T>>, FormatErrorKind> {
        if self.blocked()? {
            return Ok(None);
        }
        let open = self.lexer.expect(b'[', "opening an array")?;
        let mut array = Array::new();
        loop {
            if self.lexer.eat(b']')? {
                break;
            }
            element(self, &mut array)?;
            if !self.lexer.eat(b',')? {
                self.lexer.expect(
                    b']',
                    &format!("or `,` in the array opened at line {}", open.line),
                )?;
                break;
            }
        }
        Ok(Some(array))
    }

    fn ints(&mut self) -> Result<Authored<Array<i64>>, FormatErrorKind> {
        self.array(|parser, array| {
            let token = parser.lexer.expect_any("an integer")?;
            array.push(number(&token, "an integer")?, token.line);
            Ok(())
        })
    }

    fn floats(&mut self) -> Result<Authored<Array<f32>>, FormatErrorKind> {
        self.array(|parser, array| {
            let token = parser.lexer.expect_any("a number")?;
            array.push(number(&token, "a number")?, token.line);
            Ok(())
        })
    }

    fn vec3s(&mut self) -> Result<Authored<Array<Vec3>>, FormatErrorKind> {
        self.array(|parser, array| {
            let open = parser
                .lexer
                .expect(b'(', "opening a 3-vector `(x, y, z)`")?;
            let mut xyz = [0f32; 3];
            for (i, c) in xyz.iter_mut().enumerate() {
                if i > 0 {
                    parser
                        .lexer
                        .expect(b',', "between the 3-vector's numbers")?;
                }
                let token = parser.lexer.expect_any("a number")?;
                *c = number(&token, "a 3-vector's number")?;
            }
            parser.lexer.expect(b')', "closing a 3-vector")?;
            array.push(Vec3::from_array(xyz), open.line);
            Ok(())
        })
    }
}
