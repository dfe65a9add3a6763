//! A shot's frames split into even chunks ([`Chunk`]): the unit of work of a farm's tasks
//! (`--chunk K/N`).

use std::ops::Range;
use std::str::FromStr;

/// Chunk `index` of `count` (from 1) of a shot's frames: frames `⌊(index−1)·F/count⌋ ..
/// ⌊index·F/count⌋` of `F`, so that the chunks are as even as whole frames allow and together
/// cover the shot once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Chunk {
    /// Which chunk, from 1.
    pub index: usize,
    /// How many chunks the shot is split into.
    pub count: usize,
}

impl Chunk {
    /// Chunk `index` of `count`; refuses an index outside `1..=count`.
    pub fn new(index: usize, count: usize) -> Result<Chunk, String> {
        if count == 0 {
            return Err("a shot is split into at least 1 chunk (got 0 chunks)".into());
        }
        if index == 0 || index > count {
            return Err(format!(
                "chunk {index} of {count} is out of range (chunks are numbered 1 to {count})"
            ));
        }
        Ok(Chunk { index, count })
    }

    /// Its frames of a shot of `frames` frames; refuses more chunks than frames (a chunk would
    /// be empty).
    pub fn frames(&self, frames: usize) -> Result<Range<usize>, String> {
        if self.count > frames {
            return Err(format!(
                "{} chunks for a shot of {frames} frames: every chunk needs a frame",
                self.count
            ));
        }
        Ok((self.index - 1) * frames / self.count..self.index * frames / self.count)
    }

    /// The chunk of `count` that holds frame `frame` of a shot of `frames` frames.
    pub fn holding(frame: usize, count: usize, frames: usize) -> Chunk {
        // Chunk k holds f when ⌊(k−1)·F/n⌋ ≤ f < ⌊k·F/n⌋: the smallest k with f < ⌊k·F/n⌋.
        let index = (1..=count)
            .find(|&k| frame < k * frames / count)
            .unwrap_or(count);
        Chunk { index, count }
    }
}

impl FromStr for Chunk {
    type Err = String;

    /// `K/N`: chunk K of N, from 1.
    fn from_str(text: &str) -> Result<Chunk, String> {
        let parse = |part: &str, what: &str| {
            part.trim().parse::<usize>().map_err(|_| {
                format!(
                    "chunk `{text}`: {what} `{part}` is not a whole number (write K/N, e.g. 2/4)"
                )
            })
        };
        let (index, count) = text
            .split_once('/')
            .ok_or_else(|| format!("chunk `{text}`: write K/N, chunk K of N from 1 (e.g. 2/4)"))?;
        Chunk::new(parse(index, "K")?, parse(count, "N")?)
    }
}

impl std::fmt::Display for Chunk {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_shot_once_and_evenly() {
        for frames in [1usize, 7, 60, 61] {
            for count in 1..=frames.min(9) {
                let mut next = 0;
                for index in 1..=count {
                    let range = Chunk::new(index, count).unwrap().frames(frames).unwrap();
                    assert_eq!(range.start, next, "chunk {index}/{count} of {frames}");
                    // Even: every chunk holds ⌊F/n⌋ or ⌈F/n⌉ frames.
                    assert!(range.len() == frames / count || range.len() == frames.div_ceil(count));
                    for frame in range.clone() {
                        assert_eq!(Chunk::holding(frame, count, frames).index, index);
                    }
                    next = range.end;
                }
                assert_eq!(next, frames);
            }
        }
        assert_eq!(Chunk::new(2, 4).unwrap().frames(60), Ok(15..30));
    }

    #[test]
    fn bad_chunks_are_refused_naming_the_problem() {
        assert!(Chunk::from_str("7/6").unwrap_err().contains("out of range"));
        assert!(Chunk::from_str("0/6").unwrap_err().contains("out of range"));
        assert!(Chunk::from_str("1/0").unwrap_err().contains("at least 1"));
        assert!(Chunk::from_str("two/4").unwrap_err().contains("`two`"));
        assert!(Chunk::from_str("3").unwrap_err().contains("K/N"));
        assert!(
            Chunk::new(1, 8)
                .unwrap()
                .frames(5)
                .unwrap_err()
                .contains("8 chunks")
        );
        assert_eq!(Chunk::from_str(" 2/4"), Ok(Chunk { index: 2, count: 4 }));
    }
}
