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
    /// A surface giving way to a surface ([`gives_way`](Self::gives_way)) instead falls as the
    /// new one rises, to 0 at half the blend, on the complementary screen-door pixels: a
    /// screen-doored surface costs its whole fill at any coverage, so the old one leaves as soon
    /// as the new one is fully in. 0 for a level the section does not draw.
    pub fn coverage(&self, section: usize, level: Level, time: f64) -> f32 {
        let weight = self.blend_weight(section, time);
        let rising = (2.0 * weight).min(1.0);
        let dissolve = if level == self.current[section] {
            rising
        } else if self.gives_way(section, level) {
            1.0 - rising
        } else if self.previous(section) == Some(level) {
            1.0 - weight
        } else {
            return 0.0;
        };
        dissolve * self.shown_weight(section, time)
    }

    /// Whether `level` of section `section` is a surface (clusters or a patch) blending out to
    /// another surface: the two cross-fade on complementary screen-door pixels
    /// ([`coverage`](Self::coverage)). Strands on either side of a blend dissolve by coverage.
    pub fn gives_way(&self, section: usize, level: Level) -> bool {
        let surface = |level: Level| level != Level::StrandGroup;
        self.previous(section) == Some(level) && surface(level) && surface(self.current[section])
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

    /// Checks restored state against its invariants at `time` [s]: every blend and visibility
    /// fade started at a finite time in `[0, time]` and lasts a finite duration ≥ 0 s, a blend
    /// is between two different levels, and a fade starts from a weight in `[0, 1]`. Returns the
    /// field and what is wrong with it.
    pub(crate) fn check_at(&self, time: f64) -> std::result::Result<(), (String, String)> {
        let started = |start: f64| start.is_finite() && (0.0..=time).contains(&start);
        let lasting = |duration: f32| duration.is_finite() && duration >= 0.0;
        for (section, blend) in self.blending.iter().enumerate() {
            let Some((previous, start, duration)) = *blend else {
                continue;
            };
            let field = format!("levels.blending[{section}]");
            if previous == self.current[section] {
                return Err((field, format!("blends from {} to itself", previous.name())));
            }
            if !started(start) || !lasting(duration) {
                return Err((
                    field,
                    format!(
                        "starts at {start} s and lasts {duration} s: a blend starts in [0, {time}] s \
                         (the state's time) and lasts a finite duration of at least 0 s"
                    ),
                ));
            }
        }
        for (section, fade) in self.shown.iter().enumerate() {
            let field = format!("levels.shown[{section}]");
            if !(0.0..=1.0).contains(&fade.from) {
                return Err((
                    field,
                    format!(
                        "fades from {}: a fade starts from a weight in [0, 1]",
                        fade.from
                    ),
                ));
            }
            if !started(fade.start) || !lasting(fade.duration) {
                return Err((
                    field,
                    format!(
                        "starts at {} s and lasts {} s: a fade starts in [0, {time}] s (the \
                         state's time) and lasts a finite duration of at least 0 s",
                        fade.start, fade.duration
                    ),
                ));
            }
        }
        Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Section 0 blends from strands to clusters, section 1 from clusters to a patch, section 2
    /// from a patch to strands, each over 1 s from t = 0: the coverage of both levels at w =
    /// 0.25, 0.5 and 0.75 of the blend. The new level rises as `min(2w, 1)` in every case; the
    /// old one falls as `1 − w` unless it is a surface giving way to a surface, which falls as
    /// `1 − min(2w, 1)`, so that the two cross-fade on complementary pixels and the old one is
    /// gone when the new one is fully in.
    #[test]
    fn a_surface_gives_way_to_a_surface_by_half_the_blend() {
        let mut levels = SectionLevels::new(3, Level::StrandGroup);
        levels.switch(1, Level::Cluster, -10.0, 0.0);
        levels.switch(2, Level::Patch, -10.0, 0.0);
        levels.switch(0, Level::Cluster, 0.0, 1.0);
        levels.switch(1, Level::Patch, 0.0, 1.0);
        levels.switch(2, Level::StrandGroup, 0.0, 1.0);
        let cases = [
            (0, Level::StrandGroup, false),
            (1, Level::Cluster, true),
            (2, Level::Patch, false),
        ];
        for (section, old, gives_way) in cases {
            assert_eq!(
                levels.gives_way(section, old),
                gives_way,
                "section {section}"
            );
            assert!(!levels.gives_way(section, levels.current()[section]));
            for w in [0.25f32, 0.5, 0.75] {
                let time = f64::from(w);
                let new = levels.coverage(section, levels.current()[section], time);
                assert!(
                    (new - (2.0 * w).min(1.0)).abs() < 1e-6,
                    "section {section}, w {w}"
                );
                let expected = if gives_way {
                    1.0 - (2.0 * w).min(1.0)
                } else {
                    1.0 - w
                };
                let falling = levels.coverage(section, old, time);
                assert!(
                    (falling - expected).abs() < 1e-6,
                    "section {section}, w {w}"
                );
            }
        }
        // A level the section does not draw has no coverage and does not give way.
        assert_eq!(levels.coverage(0, Level::Patch, 0.5), 0.0);
        assert!(!levels.gives_way(0, Level::Patch));
    }
}
