//! The part of USD's text format (`.usda`) that holds `BasisCurves`: the layer's metadata
//! (`upAxis`, `metersPerUnit`), prims nested to any depth, and in every `def BasisCurves` prim the
//! attributes `type`, `basis`, `wrap`, `curveVertexCounts`, `points`, `widths`,
//! `primvars:widths` and `primvars:displayColor` (with their `:indices` and `interpolation`),
//! each as a default value and/or `.timeSamples`. Everything else (other prims, relationships,
//! variant sets, dictionaries, connections) is skipped by its brackets; composition arcs
//! (references, payloads, sublayers) are not followed and transforms are not applied.
//!
//! Values are resolved at a time while parsing, as USD does: time samples win over the default
//! at a numeric time (held before the first and after the last sample, linear in between, the
//! sample itself at its time); with no time, the default wins, else the earliest sample. Only the
//! samples that can matter are kept, so an animation costs the memory of one or two frames.

use glam::Vec3;

use super::error::FormatErrorKind;
use super::options::UpAxis;
use super::text::shorten;
use super::usda_lex::{Kind, Lexer, Token, unexpected};

/// Deepest prim nesting read (deeper is refused rather than risking the stack).
const MAX_PRIM_DEPTH: usize = 200;

/// Values of one array attribute with the line of each element.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Array<T> {
    pub(crate) values: Vec<T>,
    /// The line of each value (saturated at `u32::MAX`).
    pub(crate) lines: Vec<u32>,
}

impl<T> Array<T> {
    fn new() -> Self {
        Array {
            values: Vec::new(),
            lines: Vec::new(),
        }
    }

    fn push(&mut self, value: T, line: usize) {
        self.values.push(value);
        self.lines.push(u32::try_from(line).unwrap_or(u32::MAX));
    }

    pub(crate) fn len(&self) -> usize {
        self.values.len()
    }

    /// The line of value `i` (the attribute's when out of range).
    pub(crate) fn line(&self, i: usize, fallback: usize) -> usize {
        self.lines.get(i).map_or(fallback, |&l| l as usize)
    }
}

/// A value type that time samples interpolate.
pub(crate) trait Sample: Clone {
    /// `a` to `b` at `alpha` in `[0, 1]`.
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self;
}

impl Sample for Vec3 {
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self {
        a.lerp(*b, alpha as f32)
    }
}

impl Sample for f32 {
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self {
        (f64::from(*a) + (f64::from(*b) - f64::from(*a)) * alpha) as f32
    }
}

impl Sample for i64 {
    /// Integers are held, not interpolated (as in USD).
    fn lerp(a: &Self, _: &Self, _: f64) -> Self {
        *a
    }
}

impl Sample for String {
    fn lerp(a: &Self, _: &Self, _: f64) -> Self {
        a.clone()
    }
}

impl<T: Sample> Sample for Array<T> {
    /// Element by element when the sizes agree, else held (as in USD).
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self {
        if a.len() != b.len() {
            return a.clone();
        }
        Array {
            values: a
                .values
                .iter()
                .zip(&b.values)
                .map(|(x, y)| T::lerp(x, y, alpha))
                .collect(),
            lines: a.lines.clone(),
        }
    }
}

/// An authored value: `None` when blocked (`= None`).
type Authored<T> = Option<T>;

/// One attribute as authored: its default and the time samples that matter at the time read.
#[derive(Debug)]
pub(crate) struct Attr<T> {
    /// Line of the first declaration.
    pub(crate) line: usize,
    default: Option<Authored<T>>,
    /// The latest sample at or before the time (the earliest sample when reading with no time).
    lower: Option<(f64, Authored<T>)>,
    /// The earliest sample after the time.
    upper: Option<(f64, Authored<T>)>,
    /// The `interpolation` metadata and its line.
    pub(crate) interpolation: Option<(String, usize)>,
}

impl<T: Sample> Attr<T> {
    fn new(line: usize) -> Self {
        Attr {
            line,
            default: None,
            lower: None,
            upper: None,
            interpolation: None,
        }
    }

    /// Keeps a sample at `t` if it can matter when reading at `time`.
    fn offer(&mut self, time: Option<f64>, t: f64, value: Authored<T>) {
        match time {
            None => {
                if self.lower.as_ref().is_none_or(|(lt, _)| t < *lt) {
                    self.lower = Some((t, value));
                }
            }
            Some(time) if t <= time => {
                if self.lower.as_ref().is_none_or(|(lt, _)| t >= *lt) {
                    self.lower = Some((t, value));
                }
            }
            Some(_) => {
                if self.upper.as_ref().is_none_or(|(ut, _)| t < *ut) {
                    self.upper = Some((t, value));
                }
            }
        }
    }

    /// The value at `time` (see the module's documentation); `None` when not authored or blocked.
    pub(crate) fn resolve(self, time: Option<f64>) -> Option<T> {
        let Some(time) = time else {
            return match self.default {
                Some(value) => value,
                None => self.lower.and_then(|(_, v)| v),
            };
        };
        match (self.lower, self.upper) {
            (None, None) => self.default.flatten(),
            (Some((_, value)), None) | (None, Some((_, value))) => value,
            (Some((lt, lower)), Some((ut, upper))) => match (lower, upper) {
                (Some(a), Some(b)) => Some(T::lerp(&a, &b, (time - lt) / (ut - lt))),
                (lower, _) => lower,
            },
        }
    }
}

/// The attributes of one `def BasisCurves` prim.
#[derive(Debug)]
pub(crate) struct CurvesPrim {
    /// The prim's name (quotes included) and line.
    pub(crate) name: String,
    pub(crate) line: usize,
    pub(crate) curve_type: Option<Attr<String>>,
    pub(crate) basis: Option<Attr<String>>,
    pub(crate) wrap: Option<Attr<String>>,
    pub(crate) counts: Option<Attr<Array<i64>>>,
    pub(crate) points: Option<Attr<Array<Vec3>>>,
    pub(crate) widths: Option<Attr<Array<f32>>>,
    pub(crate) primvar_widths: Option<Attr<Array<f32>>>,
    pub(crate) width_indices: Option<Attr<Array<i64>>>,
    pub(crate) colors: Option<Attr<Array<Vec3>>>,
    pub(crate) color_indices: Option<Attr<Array<i64>>>,
}

/// What a layer holds: its axes and units and its `BasisCurves` prims, in file order.
#[derive(Debug)]
pub(crate) struct Layer {
    /// `upAxis` and its line (`Y` when not authored).
    pub(crate) up: UpAxis,
    /// `metersPerUnit` (0.01 when not authored, as in USD).
    pub(crate) meters_per_unit: f64,
    pub(crate) meters_per_unit_line: usize,
    pub(crate) prims: Vec<CurvesPrim>,
}

/// The attributes of a `BasisCurves` prim that are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Field {
    Type,
    Basis,
    Wrap,
    Counts,
    Points,
    Widths,
    PrimvarWidths,
    WidthIndices,
    Colors,
    ColorIndices,
}

impl Field {
    fn from_name(name: &str) -> Option<Field> {
        Some(match name {
            "type" => Field::Type,
            "basis" => Field::Basis,
            "wrap" => Field::Wrap,
            "curveVertexCounts" => Field::Counts,
            "points" => Field::Points,
            "widths" => Field::Widths,
            "primvars:widths" => Field::PrimvarWidths,
            "primvars:widths:indices" => Field::WidthIndices,
            "primvars:displayColor" => Field::Colors,
            "primvars:displayColor:indices" => Field::ColorIndices,
            _ => return None,
        })
    }

    /// Whether `type_name` (`[]` included) fits, and the type expected, in words.
    fn accepts(self, type_name: &str) -> (bool, &'static str) {
        let vec3 = |t: &str| {
            t.strip_suffix("[]").is_some_and(|e| {
                ["3f", "3d", "3h", "float3", "double3", "half3"]
                    .iter()
                    .any(|s| e.ends_with(s))
            })
        };
        match self {
            Field::Type | Field::Basis | Field::Wrap => (type_name == "token", "token"),
            Field::Counts | Field::WidthIndices | Field::ColorIndices => (
                matches!(type_name, "int[]" | "int64[]" | "uint[]" | "uint64[]"),
                "int[]",
            ),
            Field::Points => (vec3(type_name), "point3f[]"),
            Field::Colors => (vec3(type_name), "color3f[]"),
            Field::Widths | Field::PrimvarWidths => (
                matches!(type_name, "float[]" | "double[]" | "half[]"),
                "float[]",
            ),
        }
    }
}

/// Parses `text` (USD text, UTF-8) into its layer, resolving values at `time`.
pub(crate) fn parse_layer(text: &str, time: Option<f64>) -> Result<Layer, FormatErrorKind> {
    let mut parser = Parser {
        lexer: Lexer::new(text),
        time,
        layer: Layer {
            up: UpAxis::Y,
            meters_per_unit: 0.01,
            meters_per_unit_line: 1,
            prims: Vec::new(),
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
    Ok(parser.layer)
}

struct Parser<'a> {
    lexer: Lexer<'a>,
    time: Option<f64>,
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
        for (name, value) in self.metadata(&["upAxis", "metersPerUnit"])? {
            if name.text == "upAxis" {
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
        let mut curves =
            (specifier.text == "def" && type_name == Some("BasisCurves")).then(|| CurvesPrim {
                name: shorten(name.text),
                line: name.line,
                curve_type: None,
                basis: None,
                wrap: None,
                counts: None,
                points: None,
                widths: None,
                primvar_widths: None,
                width_indices: None,
                colors: None,
                color_indices: None,
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
                (Kind::Ident, _) => self.property(token, curves.as_mut())?,
                _ => return Err(unexpected(&token, "a property, a child prim or `}`")),
            }
        }
        if let Some(curves) = curves {
            self.layer.prims.push(curves);
        }
        Ok(())
    }

    /// A property from its first word to the end of its value and metadata.
    fn property(
        &mut self,
        first: Token<'a>,
        curves: Option<&mut CurvesPrim>,
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
        let field = curves.as_ref().and_then(|_| Field::from_name(base));
        let Some((field, curves)) = field.zip(curves) else {
            if self.lexer.eat(b'=')? {
                self.skip_value()?;
            }
            return self.optional_metadata(&[]).map(drop);
        };
        let (fits, expected) = field.accepts(&type_name);
        if !fits {
            return Err(FormatErrorKind::Syntax {
                line: type_token.line,
                message: format!(
                    "`{base}` of BasisCurves {} has type `{}`; expected `{expected}`",
                    curves.name,
                    shorten(&type_name)
                ),
            });
        }
        let line = name.line;
        let time = self.time;
        match field {
            Field::Type => {
                self.attribute(&mut curves.curve_type, line, suffix, time, Self::token)?
            }
            Field::Basis => self.attribute(&mut curves.basis, line, suffix, time, Self::token)?,
            Field::Wrap => self.attribute(&mut curves.wrap, line, suffix, time, Self::token)?,
            Field::Counts => self.attribute(&mut curves.counts, line, suffix, time, Self::ints)?,
            Field::WidthIndices => {
                self.attribute(&mut curves.width_indices, line, suffix, time, Self::ints)?
            }
            Field::ColorIndices => {
                self.attribute(&mut curves.color_indices, line, suffix, time, Self::ints)?
            }
            Field::Points => self.attribute(&mut curves.points, line, suffix, time, Self::vec3s)?,
            Field::Colors => self.attribute(&mut curves.colors, line, suffix, time, Self::vec3s)?,
            Field::Widths => {
                self.attribute(&mut curves.widths, line, suffix, time, Self::floats)?
            }
            Field::PrimvarWidths => {
                self.attribute(&mut curves.primvar_widths, line, suffix, time, Self::floats)?
            }
        }
        Ok(())
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
                    attr.offer(time, t, sample);
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
