//! Tokens of USD's text format (`.usda`) with their lines: identifiers (namespaced, `a:b.c`),
//! numbers (`-1.5e-3`, `inf`, `-nan`), strings (`"…"`, `'…'`, `"""…"""`), asset paths (`@…@`,
//! `@@@…@@@`), scene paths (`<…>`) and punctuation; `#` comments are dropped. Never panics: text
//! the format does not know is a syntax error naming its line.

use super::error::FormatErrorKind;
use super::text::shorten;

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A name or keyword: letters, digits, `_`, and `:` `.` inside (`primvars:displayColor`,
    /// `points.timeSamples`).
    Ident,
    /// A number, sign included (`-0.5`, `1e-05`, `-inf`).
    Number,
    /// A quoted string, quotes included.
    String,
    /// An asset path `@…@`.
    Asset,
    /// A scene path `<…>`.
    Path,
    /// One of `( ) [ ] { } = , ; :`.
    Punct(u8),
}

/// A token: its kind, its text in the file and the 1-based line where it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Token<'a> {
    pub(crate) kind: Kind,
    pub(crate) text: &'a str,
    pub(crate) line: usize,
}

impl Token<'_> {
    /// Whether this is the punctuation `c`.
    pub(crate) fn is(&self, c: u8) -> bool {
        self.kind == Kind::Punct(c)
    }

    /// The token as a message shows it.
    pub(crate) fn shown(&self) -> String {
        format!("`{}`", shorten(self.text))
    }
}

/// A cursor over the tokens of a text.
pub(crate) struct Lexer<'a> {
    text: &'a str,
    at: usize,
    line: usize,
    peeked: Option<Option<Token<'a>>>,
}

fn ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn ident_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b':' || b == b'.'
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `text` (line 1).
    pub(crate) fn new(text: &'a str) -> Self {
        Lexer {
            text,
            at: 0,
            line: 1,
            peeked: None,
        }
    }

    /// The line the lexer is at (where the next token starts, or the end).
    pub(crate) fn line(&self) -> usize {
        match self.peeked {
            Some(Some(token)) => token.line,
            _ => self.line,
        }
    }

    /// The next token without consuming it; `None` at the end.
    pub(crate) fn peek(&mut self) -> Result<Option<Token<'a>>, FormatErrorKind> {
        if let Some(token) = self.peeked {
            return Ok(token);
        }
        let token = self.scan()?;
        self.peeked = Some(token);
        Ok(token)
    }

    /// The next token; `None` at the end.
    pub(crate) fn next_token(&mut self) -> Result<Option<Token<'a>>, FormatErrorKind> {
        let token = self.peek()?;
        self.peeked = None;
        Ok(token)
    }

    /// The next token, which must exist; `what` names what was expected.
    pub(crate) fn expect_any(&mut self, what: &str) -> Result<Token<'a>, FormatErrorKind> {
        let line = self.line();
        self.next_token()?.ok_or_else(|| FormatErrorKind::Syntax {
            line,
            message: format!("the file ends where {what} was expected (truncated?)"),
        })
    }

    /// The next token, which must be the punctuation `c`.
    pub(crate) fn expect(&mut self, c: u8, context: &str) -> Result<Token<'a>, FormatErrorKind> {
        let what = format!("`{}` {context}", c as char);
        let token = self.expect_any(&what)?;
        if token.is(c) {
            Ok(token)
        } else {
            Err(unexpected(&token, &what))
        }
    }

    /// Consumes the next token if it is the punctuation `c`.
    pub(crate) fn eat(&mut self, c: u8) -> Result<bool, FormatErrorKind> {
        if self.peek()?.is_some_and(|t| t.is(c)) {
            self.peeked = None;
            return Ok(true);
        }
        Ok(false)
    }

    fn bytes(&self) -> &'a [u8] {
        self.text.as_bytes()
    }

    /// Skips blanks and comments, counting lines.
    fn skip_blank(&mut self) {
        let bytes = self.bytes();
        while let Some(&b) = bytes.get(self.at) {
            match b {
                b'\n' => {
                    self.line += 1;
                    self.at += 1;
                }
                b' ' | b'\t' | b'\r' => self.at += 1,
                b'#' => {
                    while bytes.get(self.at).is_some_and(|&b| b != b'\n') {
                        self.at += 1;
                    }
                }
                _ => break,
            }
        }
    }

    /// The token from `start` to the current position.
    fn token(&self, kind: Kind, start: usize, line: usize) -> Token<'a> {
        Token {
            kind,
            text: self.text.get(start..self.at).unwrap_or_default(),
            line,
        }
    }

    fn scan(&mut self) -> Result<Option<Token<'a>>, FormatErrorKind> {
        self.skip_blank();
        let bytes = self.bytes();
        let (start, line) = (self.at, self.line);
        let Some(&first) = bytes.get(start) else {
            return Ok(None);
        };
        let advance_while = |lexer: &mut Self, f: fn(u8) -> bool| {
            while lexer.bytes().get(lexer.at).is_some_and(|&b| f(b)) {
                lexer.at += 1;
            }
        };
        let kind = match first {
            b'(' | b')' | b'[' | b']' | b'{' | b'}' | b'=' | b',' | b';' | b':' => {
                self.at += 1;
                Kind::Punct(first)
            }
            b'"' | b'\'' => {
                self.string(first)?;
                Kind::String
            }
            b'@' => {
                self.delimited(b"@@@", b"@@@", "asset path")
                    .or_else(|_| self.delimited(b"@", b"@", "asset path"))?;
                Kind::Asset
            }
            b'<' => {
                self.delimited(b"<", b">", "scene path")?;
                Kind::Path
            }
            b'-' | b'+' | b'.' | b'0'..=b'9' => {
                self.at += 1;
                advance_while(self, |b| {
                    b.is_ascii_alphanumeric() || matches!(b, b'.' | b'-' | b'+' | b'_')
                });
                Kind::Number
            }
            b if ident_start(b) => {
                advance_while(self, ident_char);
                Kind::Ident
            }
            _ => {
                let shown = self
                    .text
                    .get(start..)
                    .and_then(|rest| rest.chars().next())
                    .unwrap_or('?');
                return Err(FormatErrorKind::Syntax {
                    line,
                    message: format!("unexpected character `{}`", shown.escape_debug()),
                });
            }
        };
        Ok(Some(self.token(kind, start, line)))
    }

    /// Reads a string opened by `quote` (one or three of them), escapes included.
    fn string(&mut self, quote: u8) -> Result<(), FormatErrorKind> {
        let line = self.line;
        let bytes = self.bytes();
        let triple = bytes.get(self.at..self.at + 3) == Some(&[quote; 3][..]);
        self.at += if triple { 3 } else { 1 };
        loop {
            let Some(&b) = bytes.get(self.at) else {
                return Err(FormatErrorKind::Syntax {
                    line,
                    message: "a string that is never closed (truncated?)".into(),
                });
            };
            match b {
                b'\\' => self.at += 2,
                b'\n' if !triple => {
                    return Err(FormatErrorKind::Syntax {
                        line,
                        message: "a string that is not closed on its line".into(),
                    });
                }
                b'\n' => {
                    self.line += 1;
                    self.at += 1;
                }
                _ if b == quote => {
                    if !triple {
                        self.at += 1;
                        return Ok(());
                    }
                    if bytes.get(self.at..self.at + 3) == Some(&[quote; 3][..]) {
                        self.at += 3;
                        return Ok(());
                    }
                    self.at += 1;
                }
                _ => self.at += 1,
            }
        }
    }

    /// Reads from `open` to the next `close` on the same line.
    fn delimited(&mut self, open: &[u8], close: &[u8], what: &str) -> Result<(), FormatErrorKind> {
        let bytes = self.bytes();
        if bytes.get(self.at..self.at + open.len()) != Some(open) {
            return Err(FormatErrorKind::Syntax {
                line: self.line,
                message: format!("a malformed {what}"),
            });
        }
        let from = self.at + open.len();
        let rest = bytes.get(from..).unwrap_or_default();
        let line_end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        match rest[..line_end]
            .windows(close.len())
            .position(|w| w == close)
        {
            Some(end) => {
                self.at = from + end + close.len();
                Ok(())
            }
            None => Err(FormatErrorKind::Syntax {
                line: self.line,
                message: format!("a {what} that is not closed on its line"),
            }),
        }
    }
}

/// The error for `token` found where `expected` was.
pub(crate) fn unexpected(token: &Token, expected: &str) -> FormatErrorKind {
    FormatErrorKind::Syntax {
        line: token.line,
        message: format!("expected {expected}, found {}", token.shown()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<(Kind, &str, usize)> {
        let mut lexer = Lexer::new(text);
        let mut out = Vec::new();
        while let Some(t) = lexer.next_token().unwrap() {
            out.push((t.kind, t.text, t.line));
        }
        out
    }

    #[test]
    fn tokens_carry_their_lines() {
        let text = "#usda 1.0\n(\n  doc = \"\"\"two\nlines\"\"\"\n)\ndef BasisCurves \"h\" {\n\
                    point3f[] points.timeSamples = { 0: [(-1e-05, inf, -nan)] } # c\n\
                    rel a = </x> asset b = @./a b.usda@\n}";
        let tokens = kinds(text);
        assert_eq!(tokens[0], (Kind::Punct(b'('), "(", 2));
        assert_eq!(tokens[3], (Kind::String, "\"\"\"two\nlines\"\"\"", 3));
        assert_eq!(tokens[4], (Kind::Punct(b')'), ")", 5));
        assert!(tokens.contains(&(Kind::Ident, "points.timeSamples", 7)));
        assert!(tokens.contains(&(Kind::Number, "-1e-05", 7)));
        assert!(tokens.contains(&(Kind::Ident, "inf", 7)));
        assert!(tokens.contains(&(Kind::Number, "-nan", 7)));
        assert!(tokens.contains(&(Kind::Path, "</x>", 8)));
        assert!(tokens.contains(&(Kind::Asset, "@./a b.usda@", 8)));
        assert_eq!(tokens.last(), Some(&(Kind::Punct(b'}'), "}", 9)));
    }

    #[test]
    fn unclosed_strings_and_odd_characters_name_the_line() {
        let mut lexer = Lexer::new("\n\n\"open\nx");
        assert_eq!(
            lexer.next_token().unwrap_err().to_string(),
            "line 3: a string that is not closed on its line"
        );
        let mut lexer = Lexer::new("\n\"\"\"open\n");
        assert_eq!(
            lexer.next_token().unwrap_err().to_string(),
            "line 2: a string that is never closed (truncated?)"
        );
        let mut lexer = Lexer::new("a\n  $");
        lexer.next_token().unwrap();
        assert_eq!(
            lexer.next_token().unwrap_err().to_string(),
            "line 2: unexpected character `$`"
        );
    }
}
