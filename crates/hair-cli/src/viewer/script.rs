//! Scripted input for `hairlod view --script FILE`: timed key presses, mouse drags, wheel turns
//! and screenshots, read from a small text format, so tests and CI drive the same controls a
//! user has.
//!
//! One event per line, at a displayed frame (counted from 0; events of a frame are applied in
//! file order before it is drawn, screenshots are taken after it is drawn); `#` starts a comment:
//!
//! ```text
//! # FRAME  EVENT       ARGUMENTS
//! 2        key         c              # a key: one character, or space, escape, home, f12
//! 4        drag        left 120 0     # a drag with a button (left, right, middle) by dx dy pixels
//! 4        scroll      2              # wheel notches (positive: zoom in)
//! 6        screenshot  before.png     # the window's image as a PNG (relative: to the script)
//! 9        quit                       # close the viewer
//! ```

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use super::controls::{DragButton, Input, Key};

/// What a script line does.
#[derive(Debug, Clone, PartialEq)]
pub enum ScriptEvent {
    /// An input, as if from the window.
    Input(Input),
    /// Write the frame's image to this PNG file.
    Screenshot(PathBuf),
    /// Close the viewer after the frame.
    Quit,
}

/// One timed event.
#[derive(Debug, Clone, PartialEq)]
pub struct ScriptLine {
    /// The displayed frame it happens at (from 0).
    pub frame: u64,
    /// What happens.
    pub event: ScriptEvent,
}

/// A parsed script: its events in frame order (file order within a frame).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Script {
    lines: Vec<ScriptLine>,
    /// Index of the first event not yet handed out.
    next: usize,
}

impl Script {
    /// Reads and parses `path`; relative screenshot paths are taken from the script's folder.
    pub fn read(path: &Path) -> Result<Script> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read the script {}", path.display()))?;
        let base = path.parent().unwrap_or(Path::new("."));
        Script::parse(&text, base).with_context(|| format!("in the script {}", path.display()))
    }

    /// Parses script text; relative screenshot paths are joined to `base`.
    pub fn parse(text: &str, base: &Path) -> Result<Script> {
        let mut lines = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let content = raw.split('#').next().unwrap_or("").trim();
            if content.is_empty() {
                continue;
            }
            let line = parse_line(content, base)
                .with_context(|| format!("line {}: `{}`", index + 1, raw.trim()))?;
            lines.push(line);
        }
        // A stable sort keeps file order within a frame.
        lines.sort_by_key(|line| line.frame);
        Ok(Script { lines, next: 0 })
    }

    /// The events of frame `frame` (and of any earlier frame not yet handed out), in order.
    pub fn take_due(&mut self, frame: u64) -> Vec<ScriptEvent> {
        let start = self.next;
        while self.next < self.lines.len() && self.lines[self.next].frame <= frame {
            self.next += 1;
        }
        self.lines[start..self.next]
            .iter()
            .map(|line| line.event.clone())
            .collect()
    }

    /// The last frame with an event (`None` for an empty script).
    pub fn last_frame(&self) -> Option<u64> {
        self.lines.last().map(|line| line.frame)
    }
}

/// Parses one non-empty line without its comment.
fn parse_line(content: &str, base: &Path) -> Result<ScriptLine> {
    let words: Vec<&str> = content.split_whitespace().collect();
    let frame: u64 = words[0]
        .parse()
        .with_context(|| format!("`{}` is not a frame number (0, 1, 2, …)", words[0]))?;
    let Some(&kind) = words.get(1) else {
        bail!("no event after the frame number (key, drag, scroll, screenshot or quit)");
    };
    let arguments = &words[2..];
    let count = |expected: usize, usage: &str| -> Result<()> {
        if arguments.len() != expected {
            bail!("`{kind}` takes {usage}");
        }
        Ok(())
    };
    let number = |word: &str, what: &str| -> Result<f32> {
        word.parse::<f32>()
            .ok()
            .filter(|value| value.is_finite())
            .with_context(|| format!("`{word}` is not a finite number of {what}"))
    };
    let event = match kind.to_ascii_lowercase().as_str() {
        "key" => {
            count(1, "one key: a character, or space, escape, home, f12")?;
            let key = Key::parse(arguments[0]).with_context(|| {
                format!(
                    "unknown key `{}`: one character, or space, escape, home, f12",
                    arguments[0]
                )
            })?;
            ScriptEvent::Input(Input::Key(key))
        }
        "drag" => {
            count(3, "a button (left, right, middle) and dx dy [pixels]")?;
            let button = DragButton::parse(arguments[0]).with_context(|| {
                format!("unknown button `{}`: left, right or middle", arguments[0])
            })?;
            ScriptEvent::Input(Input::Drag {
                button,
                dx: number(arguments[1], "pixels")?,
                dy: number(arguments[2], "pixels")?,
            })
        }
        "scroll" => {
            count(1, "a number of wheel notches (positive: zoom in)")?;
            ScriptEvent::Input(Input::Scroll(number(arguments[0], "notches")?))
        }
        "screenshot" => {
            count(1, "one PNG path")?;
            ScriptEvent::Screenshot(base.join(arguments[0]))
        }
        "quit" => {
            count(0, "no arguments")?;
            ScriptEvent::Quit
        }
        other => bail!("unknown event `{other}`: key, drag, scroll, screenshot or quit"),
    };
    Ok(ScriptLine { frame, event })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_come_out_at_their_frames_in_file_order() {
        let text = "# a comment\n\
                    4 drag left 120 -3.5   # orbit\n\
                    2 key c\n\
                    4 scroll 2\n\
                    \n\
                    6 screenshot shot.png\n\
                    9 quit\n";
        let mut script = Script::parse(text, Path::new("/tmp/s")).unwrap();
        assert_eq!(script.last_frame(), Some(9));
        assert!(script.take_due(1).is_empty());
        assert_eq!(
            script.take_due(2),
            [ScriptEvent::Input(Input::Key(Key::Char('c')))]
        );
        assert_eq!(
            script.take_due(5),
            [
                ScriptEvent::Input(Input::Drag {
                    button: DragButton::Left,
                    dx: 120.0,
                    dy: -3.5
                }),
                ScriptEvent::Input(Input::Scroll(2.0)),
            ]
        );
        assert_eq!(
            script.take_due(6),
            [ScriptEvent::Screenshot(PathBuf::from("/tmp/s/shot.png"))]
        );
        assert_eq!(script.take_due(100), [ScriptEvent::Quit]);
        assert!(script.take_due(101).is_empty());
    }

    #[test]
    fn bad_lines_name_the_line_and_the_problem() {
        for (text, expected) in [
            ("x key c", "not a frame number"),
            ("3", "no event"),
            ("3 jump", "unknown event `jump`"),
            ("3 key", "takes one key"),
            ("3 key shift", "unknown key `shift`"),
            ("3 drag up 1 2", "unknown button `up`"),
            ("3 drag left 1 nan", "`nan` is not a finite number"),
            ("3 scroll", "wheel notches"),
            ("3 quit now", "no arguments"),
        ] {
            let error = Script::parse(&format!("1 key c\n{text}\n"), Path::new(".")).unwrap_err();
            let message = format!("{error:#}");
            assert!(
                message.contains("line 2") && message.contains(expected),
                "{text}: {message}"
            );
        }
    }
}
