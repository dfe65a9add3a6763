//! The transform attributes the USD text parser (`usda_parse.rs`) collects while meshes are read:
//! a prim's `xformOpOrder` (a `token[]`) and its `xformOp:` attributes, each value a number or a
//! tuple of numbers (vectors, quaternions, matrices' rows) flattened in order, for the mesh readers
//! to compose (`usd_xform.rs`).

use super::super::error::FormatErrorKind;
use super::super::text::shorten;
use super::super::usda_lex::{Kind, Token, unexpected};
use super::super::usda_prims::XformPrim;
use super::super::usda_values::{Array, Authored};
use super::{Parser, number, unquote};

impl<'a> Parser<'a> {
    /// A transform attribute of a prim whose ops are collected: `xformOpOrder` (a `token[]`) or
    /// an `xformOp:` (numbers of any shape, flattened).
    pub(super) fn xform_property(
        &mut self,
        xform: &mut XformPrim,
        type_name: &str,
        type_token: &Token<'a>,
        base: &str,
        suffix: Option<&str>,
        line: usize,
    ) -> Result<(), FormatErrorKind> {
        if base == "xformOpOrder" {
            if type_name != "token[]" {
                return Err(FormatErrorKind::Syntax {
                    line: type_token.line,
                    message: format!(
                        "`xformOpOrder` of prim {} has type `{}`; expected `token[]`",
                        xform.path,
                        shorten(type_name)
                    ),
                });
            }
            return self.attribute(&mut xform.order, line, suffix, None, Self::tokens);
        }
        let index = match xform.ops.iter().position(|(name, _)| name == base) {
            Some(index) => index,
            None => {
                xform.ops.push((base.to_owned(), None));
                xform.ops.len() - 1
            }
        };
        self.attribute(&mut xform.ops[index].1, line, suffix, None, Self::numbers)
    }

    /// `["a", "b"]`: tokens in quotes.
    fn tokens(&mut self) -> Result<Authored<Array<String>>, FormatErrorKind> {
        self.array(|parser, array| {
            let token = parser.lexer.expect_any("a token in quotes")?;
            if token.kind != Kind::String {
                return Err(unexpected(&token, "a token in quotes"));
            }
            array.push(unquote(&token).to_owned(), token.line);
            Ok(())
        })
    }

    /// A number or a tuple of numbers, tuples nested at most two deep (`(1, 2, 3)`, a
    /// `matrix4d`'s `((…), (…), (…), (…))`), flattened in order.
    fn numbers(&mut self) -> Result<Authored<Array<f64>>, FormatErrorKind> {
        if self.blocked()? {
            return Ok(None);
        }
        let mut array = Array::new();
        let mut depth = 0usize;
        loop {
            let token = self.lexer.expect_any("a number or `(`")?;
            if token.is(b'(') {
                depth += 1;
                if depth > 2 {
                    return Err(unexpected(
                        &token,
                        "a number (tuples nest two deep at most)",
                    ));
                }
                continue;
            }
            array.push(number(&token, "a transform value")?, token.line);
            loop {
                if depth == 0 {
                    return Ok(Some(array));
                }
                if self.lexer.eat(b')')? {
                    depth -= 1;
                    continue;
                }
                self.lexer.expect(b',', "`,` or `)` in a tuple")?;
                // A trailing comma before the closing bracket.
                if self.lexer.eat(b')')? {
                    depth -= 1;
                    continue;
                }
                break;
            }
        }
    }
}
