//! The viewer's controls: the keys and mouse gestures it knows ([`Input`]) and what each one
//! does ([`Action`]). The window and a `--script` file both produce [`Input`]s, so a script
//! drives exactly the controls a user has.

use std::fmt;

/// A key the viewer listens to, independent of the windowing system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// A printable key, lower-case (`c`, `1`, `[`, …).
    Char(char),
    /// The space bar.
    Space,
    /// Escape.
    Escape,
    /// Home.
    Home,
    /// F12.
    F12,
}

impl Key {
    /// Parses a key name as a script writes it: one character (`c`, `.`, `]`), or `space`,
    /// `escape` (`esc`), `home`, `f12`; case-insensitive.
    pub fn parse(name: &str) -> Option<Key> {
        let lower = name.to_ascii_lowercase();
        match lower.as_str() {
            "space" => Some(Key::Space),
            "escape" | "esc" => Some(Key::Escape),
            "home" => Some(Key::Home),
            "f12" => Some(Key::F12),
            _ => {
                let mut chars = lower.chars();
                match (chars.next(), chars.next()) {
                    (Some(c), None) if !c.is_whitespace() => Some(Key::Char(c)),
                    _ => None,
                }
            }
        }
    }
}

impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Key::Char(c) => write!(f, "{c}"),
            Key::Space => f.write_str("space"),
            Key::Escape => f.write_str("escape"),
            Key::Home => f.write_str("home"),
            Key::F12 => f.write_str("f12"),
        }
    }
}

/// A mouse button that drags.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DragButton {
    /// Left: orbit.
    Left,
    /// Right: pan.
    Right,
    /// Middle: pan.
    Middle,
}

impl DragButton {
    /// Parses `left`, `right` or `middle` (case-insensitive).
    pub fn parse(name: &str) -> Option<DragButton> {
        match name.to_ascii_lowercase().as_str() {
            "left" => Some(DragButton::Left),
            "right" => Some(DragButton::Right),
            "middle" => Some(DragButton::Middle),
            _ => None,
        }
    }
}

/// One input event, from the window or a script.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input {
    /// A key pressed.
    Key(Key),
    /// The mouse moved by (`dx`, `dy`) [pixels, +x right, +y down] with `button` held.
    Drag {
        /// The button held.
        button: DragButton,
        /// Horizontal motion [pixels].
        dx: f32,
        /// Vertical motion [pixels].
        dy: f32,
    },
    /// The wheel turned by `notches` (positive: away from the user, zoom in).
    Scroll(f32),
}

/// A level the user asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LevelChoice {
    /// Automatic levels (§7).
    Auto,
    /// Every section at strand groups.
    Strands,
    /// Every section at clusters.
    Clusters,
    /// Every section at patches.
    Patches,
}

impl LevelChoice {
    /// The next choice in the cycle auto → strands → clusters → patches → auto.
    pub fn next(self) -> LevelChoice {
        match self {
            LevelChoice::Auto => LevelChoice::Strands,
            LevelChoice::Strands => LevelChoice::Clusters,
            LevelChoice::Clusters => LevelChoice::Patches,
            LevelChoice::Patches => LevelChoice::Auto,
        }
    }

    /// A short name for the HUD.
    pub fn name(self) -> &'static str {
        match self {
            LevelChoice::Auto => "auto",
            LevelChoice::Strands => "strands",
            LevelChoice::Clusters => "clusters",
            LevelChoice::Patches => "patches",
        }
    }
}

/// What an input asks the viewer to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// Turn the camera around its target by (`dx`, `dy`) [pixels of drag].
    Orbit {
        /// Horizontal drag [pixels].
        dx: f32,
        /// Vertical drag [pixels].
        dy: f32,
    },
    /// Move the camera and its target sideways by (`dx`, `dy`) [pixels of drag].
    Pan {
        /// Horizontal drag [pixels].
        dx: f32,
        /// Vertical drag [pixels].
        dy: f32,
    },
    /// Move the camera towards its target by `notches` of the wheel (negative: away).
    Zoom(f32),
    /// Back to the scene's camera (its path, followed frame by frame).
    ResetView,
    /// Play or pause the simulation.
    TogglePause,
    /// Advance one frame (while paused).
    Step,
    /// Shaded, or colour-coded by level (strands yellow, clusters red, patches blue).
    ToggleColorCode,
    /// The next level choice (auto, strands, clusters, patches).
    CycleLevel,
    /// A level choice.
    SetLevel(LevelChoice),
    /// Multiply the pixel tolerance by this factor.
    ScaleTolerance(f32),
    /// Frame budget on or off.
    ToggleBudget,
    /// Multiply the frame budget by this factor.
    ScaleBudget(f64),
    /// Wind on or off.
    ToggleWind,
    /// The next head motion (the scene's, still, shake, nod).
    CycleMotion,
    /// Write the window's image as a PNG.
    Screenshot,
    /// Show or hide the heads-up display.
    ToggleHud,
    /// Close the viewer.
    Quit,
}

/// The factor of one tolerance step ([`Action::ScaleTolerance`]): √2, two steps double it.
pub const TOLERANCE_STEP: f32 = std::f32::consts::SQRT_2;
/// The factor of one frame-budget step ([`Action::ScaleBudget`]).
pub const BUDGET_STEP: f64 = 1.25;

/// The action of an input, or `None` for a key the viewer does not use.
pub fn action_of(input: Input) -> Option<Action> {
    match input {
        Input::Drag {
            button: DragButton::Left,
            dx,
            dy,
        } => Some(Action::Orbit { dx, dy }),
        Input::Drag { dx, dy, .. } => Some(Action::Pan { dx, dy }),
        Input::Scroll(notches) => Some(Action::Zoom(notches)),
        Input::Key(key) => key_action(key),
    }
}

/// The action of a key (see [`KEY_HELP`]).
fn key_action(key: Key) -> Option<Action> {
    Some(match key {
        Key::Space => Action::TogglePause,
        Key::Escape => Action::Quit,
        Key::Home => Action::ResetView,
        Key::F12 => Action::Screenshot,
        Key::Char(c) => match c {
            'r' => Action::ResetView,
            '.' | 'n' => Action::Step,
            'c' => Action::ToggleColorCode,
            'l' => Action::CycleLevel,
            '0' => Action::SetLevel(LevelChoice::Auto),
            '1' => Action::SetLevel(LevelChoice::Strands),
            '2' => Action::SetLevel(LevelChoice::Clusters),
            '3' => Action::SetLevel(LevelChoice::Patches),
            '[' => Action::ScaleTolerance(1.0 / TOLERANCE_STEP),
            ']' => Action::ScaleTolerance(TOLERANCE_STEP),
            'b' => Action::ToggleBudget,
            '-' => Action::ScaleBudget(1.0 / BUDGET_STEP),
            '=' | '+' => Action::ScaleBudget(BUDGET_STEP),
            'w' => Action::ToggleWind,
            'm' => Action::CycleMotion,
            's' => Action::Screenshot,
            'h' => Action::ToggleHud,
            'q' => Action::Quit,
            _ => return None,
        },
    })
}

/// Every control, one line each, for the HUD and `hairlod view --help`.
pub const KEY_HELP: &[(&str, &str)] = &[
    ("left drag", "orbit"),
    ("right/middle drag", "pan"),
    ("wheel", "zoom"),
    ("r, home", "reset view (follow the scene's camera)"),
    ("space", "play / pause"),
    (". or n", "single step"),
    (
        "c",
        "level colours (strands yellow, clusters red, patches blue)",
    ),
    (
        "l; 0 1 2 3",
        "cycle level; auto, strands, clusters, patches",
    ),
    ("[ ]", "pixel tolerance / or × √2"),
    ("b; - =", "frame budget on/off; budget / or × 1.25"),
    ("w", "wind on/off"),
    ("m", "head motion: scene's, still, shake, nod"),
    ("s, f12", "screenshot (PNG)"),
    ("h", "HUD on/off"),
    ("q, escape", "quit"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_parse_by_name_and_character() {
        assert_eq!(Key::parse("C"), Some(Key::Char('c')));
        assert_eq!(Key::parse("space"), Some(Key::Space));
        assert_eq!(Key::parse("Esc"), Some(Key::Escape));
        assert_eq!(Key::parse("]"), Some(Key::Char(']')));
        assert_eq!(Key::parse("cc"), None);
        assert_eq!(Key::parse(""), None);
    }

    #[test]
    fn every_documented_key_has_an_action() {
        for key in "rnc.l0123[]b-=wmshq".chars() {
            assert!(action_of(Input::Key(Key::Char(key))).is_some(), "{key}");
        }
        for key in [Key::Space, Key::Escape, Key::Home, Key::F12] {
            assert!(action_of(Input::Key(key)).is_some(), "{key}");
        }
        assert_eq!(action_of(Input::Key(Key::Char('z'))), None);
    }

    #[test]
    fn drags_orbit_with_the_left_button_and_pan_with_the_others() {
        let drag = |button| Input::Drag {
            button,
            dx: 3.0,
            dy: -1.0,
        };
        assert_eq!(
            action_of(drag(DragButton::Left)),
            Some(Action::Orbit { dx: 3.0, dy: -1.0 })
        );
        assert_eq!(
            action_of(drag(DragButton::Right)),
            Some(Action::Pan { dx: 3.0, dy: -1.0 })
        );
        assert_eq!(action_of(Input::Scroll(2.0)), Some(Action::Zoom(2.0)));
    }

    #[test]
    fn the_level_cycle_visits_every_choice() {
        let mut choice = LevelChoice::Auto;
        let mut seen = Vec::new();
        for _ in 0..4 {
            seen.push(choice.name());
            choice = choice.next();
        }
        assert_eq!(choice, LevelChoice::Auto);
        assert_eq!(seen, ["auto", "strands", "clusters", "patches"]);
    }
}
