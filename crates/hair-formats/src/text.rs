//! Line-by-line reading of text formats (`.tfxmesh`, OBJ) that never panics: lines numbered from
//! 1, comments and blank lines dropped, numbers parsed with the line named in every error.

use std::str::FromStr;

use super::error::FormatErrorKind;

/// `bytes` as UTF-8 text, or a syntax error naming the line of the first byte that is not.
pub(crate) fn utf8_text(bytes: &[u8]) -> Result<&str, FormatErrorKind> {
    std::str::from_utf8(bytes).map_err(|error| {
        let valid = &bytes[..error.valid_up_to()];
        FormatErrorKind::Syntax {
            line: 1 + valid.iter().filter(|&&b| b == b'\n').count(),
            message: "not UTF-8 text".into(),
        }
    })
}

/// The lines of `bytes` with their 1-based numbers, `\r\n` or `\n` ended, without what follows a
/// `#`, trimmed, blank ones left out. A line that is not UTF-8 is a syntax error.
pub(crate) fn lines(
    bytes: &[u8],
) -> impl Iterator<Item = Result<(usize, &str), FormatErrorKind>> + '_ {
    bytes
        .split(|&b| b == b'\n')
        .enumerate()
        .filter_map(|(index, raw)| {
            let line = index + 1;
            let text = match std::str::from_utf8(raw) {
                Ok(text) => text,
                Err(error) => {
                    return Some(Err(FormatErrorKind::Syntax {
                        line,
                        message: format!(
                            "not UTF-8 text (byte {} of the line)",
                            error.valid_up_to() + 1
                        ),
                    }));
                }
            };
            let text = text.split('#').next().unwrap_or_default().trim();
            (!text.is_empty()).then_some(Ok((line, text)))
        })
}

/// Parses `token` as a `T`, naming `what` and the line when it is missing or malformed.
pub(crate) fn parse<T: FromStr>(
    token: Option<&str>,
    line: usize,
    what: &str,
) -> Result<T, FormatErrorKind> {
    let Some(token) = token else {
        return Err(FormatErrorKind::Syntax {
            line,
            message: format!("missing {what}"),
        });
    };
    token.parse().map_err(|_| FormatErrorKind::Syntax {
        line,
        message: format!("{what} `{}` is not a valid number", shorten(token)),
    })
}

/// `text`, cut to 40 characters for a message.
pub(crate) fn shorten(text: &str) -> String {
    let mut short: String = text.chars().take(40).collect();
    if short.len() < text.len() {
        short.push('…');
    }
    short
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_numbered_and_comments_dropped() {
        let text = b"# header\r\nv 1 2 3 # a point\n\n  l 1 2\n";
        let lines: Vec<_> = lines(text).collect::<Result<_, _>>().unwrap();
        assert_eq!(lines, [(2, "v 1 2 3"), (4, "l 1 2")]);
        let error = super::lines(b"ok\n\xff\n").nth(1).unwrap().unwrap_err();
        assert_eq!(
            error.to_string(),
            "line 2: not UTF-8 text (byte 1 of the line)"
        );
    }

    #[test]
    fn numbers_name_the_line() {
        assert_eq!(parse::<f32>(Some("1.5"), 3, "x"), Ok(1.5));
        let error = parse::<u32>(Some("-4"), 7, "vertex index").unwrap_err();
        assert_eq!(
            error.to_string(),
            "line 7: vertex index `-4` is not a valid number"
        );
        let error = parse::<f32>(None, 8, "coordinate y").unwrap_err();
        assert_eq!(error.to_string(), "line 8: missing coordinate y");
    }
}
