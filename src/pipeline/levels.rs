//! Level switches of sections: the current and (while blending) previous level of each, and
//! their visibility fades. Part of the pipeline's state (§4.2, §7).

use hair_core::Level;
use serde::{Deserialize, Serialize};

/// Every section's current level and, while a transition blends, the level it comes from; and
/// whether it is drawn, fading in or out over the same blend when it comes into view or leaves
/// it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionLevels {
    current: Vec<Level>,
    /// `(previous level, blend start [s], blend duration [s])` of sections still blending.
    blending: Vec<Option<(Level, f64, f32)>>,
    /// Per section, its visibility fade: see [`VisibilityFade`].
    shown: Vec<VisibilityFade>,
}

/// How much of a section is drawn: it fades towards `visible` (1) or hidden (0) from `from` at
/// `start` [s], by `1 / duration` per second (at once for a duration of 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
struct VisibilityFade {
    visible: bool,
    start: f64,
    from: f32,
    duration: f32,
}

impl VisibilityFade {
    /// How much is drawn at `time` [s], in `[0, 1]`.
    fn weight(&self, time: f64) -> f32 {
        let target = if self.visible { 1.0 } else { 0.0 };
        if self.duration <= 0.0 {
            return target;
        }
        let moved = ((time - self.start) / f64::from(self.duration)).max(0.0) as f32;
        if self.visible {
            (self.from + moved).min(1.0)
        } else {
            (self.from - moved).max(0.0)
        }
    }
}

impl SectionLevels {
    /// `sections` sections at `level`, none blending.
    pub fn new(sections: usize, level: Level) -> Self {
        SectionLevels {
            current: vec![level; sections],
            blending: vec![None; sections],
            shown: vec![
                VisibilityFade {
                    visible: true,
                    start: 0.0,
                    from: 1.0,
                    duration: 0.0,
                };
                sections
            ],
        }
    }

    /// Marks `section` visible or hidden from `time` [s]: with `fade` > 0 s it fades in or out
    /// over that long (from wherever it is), else at once. Returns whether its visibility changed.
    pub fn set_visible(&mut self, section: usize, visible: bool, time: f64, fade: f32) -> bool {
        let old = self.shown[section];
        if old.visible == visible {
            return false;
        }
        self.shown[section] = VisibilityFade {
            visible,
            start: time,
            from: old.weight(time),
            duration: fade.max(0.0),
        };
        true
    }

    /// How much of section `section` is drawn at `time` [s], in `[0, 1]`: 1 when visible and
    /// faded in, 0 when hidden and faded out.
    pub fn shown_weight(&self, section: usize, time: f64) -> f32 {
        self.shown[section].weight(time)
    }

    /// The current level of each section.
    pub fn current(&self) -> &[Level] {
        &self.current
    }

    /// The level section `section` blends from, if it is blending.
    pub fn previous(&self, section: usize) -> Option<Level> {
        self.blending[section].map(|(level, _, _)| level)
    }

    /// How far section `section`'s blend has gone at `time` [s], in `[0, 1]` (1: not blending).
    pub fn blend_weight(&self, section: usize, time: f64) -> f32 {
        match self.blending[section] {
            Some((_, start, duration)) if duration > 0.0 => {
                (((time - start) / f64::from(duration)) as f32).clamp(0.0, 1.0)
            }
            _ => 1.0,
        }
    }

    /// How much of `level` of section `section` is drawn at `time` [s], in `[0, 1]`: the
    /// section's shown weight times the blend's dissolve, in which the new level's coverage rises
    /// from 0 to 1 over the first half of the blend while the old one's falls from 1 to 0 over the
    /// whole blend (no frame shows less hair than either level; the old level's strands, drawn
    /// only as far as their coverage, cost half as much over the blend as drawing them whole).
    /// 0 for a level the section does not draw.
    pub fn coverage(&self, section: usize, level: Level, time: f64) -> f32 {
        let weight = self.blend_weight(section, time);
        let dissolve = if level == self.current[section] {
            (2.0 * weight).min(1.0)
        } else if self.previous(section) == Some(level) {
            1.0 - weight
        } else {
            return 0.0;
        };
        dissolve * self.shown_weight(section, time)
    }

    /// Switches `section` to `level` at `time` [s]; with `blend` > 0 s the old level stays
    /// simulated and drawn (fading) for that long.
    pub fn switch(&mut self, section: usize, level: Level, time: f64, blend: f32) {
        let old = self.current[section];
        self.current[section] = level;
        self.blending[section] = if blend > 0.0 && old != level {
            Some((old, time, blend))
        } else {
            None
        };
    }

    /// Ends the blends that are over at `time` [s]; returns whether any ended.
    pub fn blends_finished(&mut self, time: f64) -> bool {
        let mut ended = false;
        for blend in &mut self.blending {
            if let Some((_, start, duration)) = *blend
                && time - start >= f64::from(duration)
            {
                *blend = None;
                ended = true;
            }
        }
        ended
    }

    /// Sections blending now.
    pub fn blending_count(&self) -> usize {
        self.blending.iter().filter(|b| b.is_some()).count()
    }

    /// The levels section `section` is drawn at: its current level, and its previous one while
    /// blending.
    pub fn drawn(&self, section: usize) -> impl Iterator<Item = Level> + use<> {
        std::iter::once(self.current[section]).chain(self.previous(section))
    }

    /// Number of sections.
    pub fn section_count(&self) -> usize {
        self.current.len()
    }

    /// Whether every per-section list has `sections` entries (a check on restored state).
    pub fn is_consistent(&self, sections: usize) -> bool {
        self.current.len() == sections
            && self.blending.len() == sections
            && self.shown.len() == sections
    }

    /// The sections simulated at `level` (current or blending from it), ascending.
    pub fn members(&self, level: Level) -> Vec<usize> {
        (0..self.current.len())
            .filter(|&s| self.current[s] == level || self.previous(s) == Some(level))
            .collect()
    }
}
