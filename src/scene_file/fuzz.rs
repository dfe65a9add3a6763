//! Fuzz-style tests of scene files under plain `cargo test` (proptest, fixed seeds, a bounded
//! number of cases): `scenes/example.toml`, which sets every field, with random mutations of its
//! bytes and of its values (numbers set to huge, tiny, negative and non-finite values, strings to
//! other words), parsed and resolved. Each case returns a shot or an error that names a field or
//! the TOML's line, and never panics.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

use super::SceneFile;

/// Cases per kind of mutation.
const CASES: u32 = 400;

/// Values a number of the scene may be replaced by: the edges of `f32`, zero, negatives, TOML's
/// own infinities and NaN, and integers past every range.
const NUMBERS: [&str; 14] = [
    "0",
    "-1",
    "1e38",
    "-1e38",
    "1e-38",
    "3.5e38",
    "inf",
    "-inf",
    "nan",
    "4294967296",
    "-0.0",
    "1e300",
    "18446744073709551616",
    "0.5",
];

/// Words a string of the scene may be replaced by.
const WORDS: [&str; 6] = ["", "nope", "auto", "strands", "../", "x.tfx"];

fn runner(seed: u8) -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases: CASES,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

/// Parses and resolves `text`; any result is fine, a panic fails the test (proptest reports
/// the input).
fn parse_and_resolve(text: &str) {
    match SceneFile::parse(text) {
        Ok(file) => {
            if let Err(error) = file.resolve() {
                let message = error.to_string();
                assert!(!message.is_empty());
                assert!(!message.contains("Some("), "debug text in {message:?}");
            }
        }
        Err(error) => assert!(!error.to_string().is_empty()),
    }
}

/// A byte range `(start, end)` of a value in the text.
type Span = (usize, usize);

/// The byte offsets of every number and every quoted string's contents in `text`, outside
/// comments.
fn value_spans(text: &str) -> (Vec<Span>, Vec<Span>) {
    let (mut numbers, mut strings) = (Vec::new(), Vec::new());
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split('#').next().unwrap_or("");
        let bytes = code.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            if bytes[i] == b'"' {
                let end = code[i + 1..].find('"').map_or(bytes.len(), |e| i + 1 + e);
                strings.push((offset + i + 1, offset + end));
                i = end + 1;
            } else if bytes[i].is_ascii_digit()
                && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric() && bytes[i - 1] != b'_')
            {
                let start = if i > 0 && bytes[i - 1] == b'-' {
                    i - 1
                } else {
                    i
                };
                let mut end = i;
                while end < bytes.len()
                    && (bytes[end].is_ascii_digit() || b".eE-+_".contains(&bytes[end]))
                {
                    end += 1;
                }
                numbers.push((offset + start, offset + end));
                i = end;
            } else {
                i += 1;
            }
        }
        offset += line.len();
    }
    (numbers, strings)
}

#[test]
fn mutated_values_of_the_example_scene_are_shots_or_errors() {
    let text = include_str!("../../scenes/example.toml");
    let (numbers, strings) = value_spans(text);
    assert!(
        numbers.len() > 30 && strings.len() > 10,
        "{} {}",
        numbers.len(),
        strings.len()
    );
    let edits = prop::collection::vec(
        (
            any::<bool>(),
            any::<prop::sample::Index>(),
            0..NUMBERS.len(),
            0..WORDS.len(),
        ),
        1..4,
    );
    runner(7)
        .run(&edits, |edits| {
            let mut spans: Vec<((usize, usize), &str)> = edits
                .iter()
                .map(|&(number, index, n, w)| {
                    if number {
                        (numbers[index.index(numbers.len())], NUMBERS[n])
                    } else {
                        (strings[index.index(strings.len())], WORDS[w])
                    }
                })
                .collect();
            // Apply from the end so earlier offsets hold; one edit per span.
            spans.sort_by_key(|&((start, _), _)| std::cmp::Reverse(start));
            spans.dedup_by_key(|&mut ((start, _), _)| start);
            let mut edited = text.to_string();
            for ((start, end), value) in spans {
                edited.replace_range(start..end, value);
            }
            parse_and_resolve(&edited);
            Ok(())
        })
        .unwrap();
}

#[test]
fn mutated_bytes_of_the_example_scene_are_shots_or_errors() {
    let text = include_str!("../../scenes/example.toml").as_bytes();
    let edits = prop::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0..3_u8), 1..8);
    runner(11)
        .run(&edits, |edits| {
            let mut bytes = text.to_vec();
            for (index, byte, kind) in edits {
                let at = index.index(bytes.len());
                match kind {
                    0 => bytes[at] = byte,
                    1 => bytes.insert(at, byte),
                    _ => {
                        bytes.remove(at);
                    }
                }
            }
            parse_and_resolve(&String::from_utf8_lossy(&bytes));
            Ok(())
        })
        .unwrap();
}
