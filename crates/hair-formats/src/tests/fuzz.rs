//! Fuzz-style tests under plain `cargo test` (proptest, fixed seeds, a bounded number of cases):
//! every reader gets random bytes, valid files with random mutations (flipped bytes, truncations,
//! inserted and removed bytes, header counts set to huge values) and must return a result or an
//! error, never panic; a result must be well formed and no larger than the file allows.

use std::cell::Cell;

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

use crate::cyhair::tests::sample_curves;
use crate::tfx::tests::{tfx3_bytes, tfx4_bytes, two_strands};
use crate::tfxmesh::tests::TETRAHEDRON;
use crate::usc::tests::{strands_with_empty_roots, usc_bytes};
use crate::{
    Curves, FormatError, ImportOptions, read_alembic, read_alembic_mesh_sequence, read_hair,
    read_obj_curves, read_obj_mesh, read_tfx, read_tfxmesh, read_usc_data, read_usd_mesh,
    read_usd_mesh_sequence, read_usda, read_usda_at, read_usdc, write_hair_bytes,
};
use hair_core::MeshSequence;
use hair_core::mesh::TriangleMesh;

/// Cases per target and kind of input.
const RANDOM_CASES: u32 = 1000;
/// Mutated-file cases per target.
const MUTATED_CASES: u32 = 3000;

/// A reader under test: the number of points (or vertices) it read, after checking its result.
type Reader = fn(&[u8], &ImportOptions) -> Result<usize, FormatError>;

/// One reader with a valid file to mutate.
struct Target {
    name: &'static str,
    read: Reader,
    seed: Vec<u8>,
    /// Byte offsets of the header counts and data offsets that the reader uses, to set to huge
    /// values.
    count_fields: &'static [usize],
    /// The fewest bytes a point takes in the file (bounds what a result may hold).
    min_point_bytes: usize,
}

/// Checks what a curve reader returned, and returns its point count.
fn checked_curves(result: Result<Curves, FormatError>) -> Result<usize, FormatError> {
    let curves = result?;
    assert_eq!(curves.check_layout(), Ok(()));
    assert!(curves.curve_count() >= 1);
    for curve in curves.iter() {
        assert!(curve.len() >= 2);
        assert!(curve.windows(2).all(|w| w[0] != w[1]));
    }
    Ok(curves.point_count())
}

/// Reads Alembic, and fails on a panic that the reader's last guard caught in `ogawa-rs`: the
/// checks before the crate must leave it nothing to panic on.
fn alembic_without_panic(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    let result = read_alembic(bytes, options);
    if let Err(error) = &result {
        assert!(
            !error.to_string().contains("failed on this archive"),
            "{error}"
        );
    }
    result
}

/// Checks what a mesh reader returned, and returns its vertex count.
fn checked_mesh(result: Result<TriangleMesh, FormatError>) -> Result<usize, FormatError> {
    let mesh = result?;
    assert_eq!(mesh.validate(), Ok(()));
    assert!(mesh.triangle_count() >= 1);
    assert_eq!(mesh.normals.len(), mesh.vertex_count());
    Ok(mesh.vertex_count())
}

/// Checks what a mesh sequence reader returned, and returns its vertex count (samples at time
/// codes where only a transform has a sample hold no points of their own in the file).
fn checked_sequence(result: Result<MeshSequence, FormatError>) -> Result<usize, FormatError> {
    let sequence = result?;
    assert!(sequence.sample_count() >= 1);
    assert!(!sequence.triangles().is_empty());
    assert!(sequence.times().windows(2).all(|w| w[0] < w[1]));
    for s in 0..sequence.sample_count() {
        assert!(sequence.sample_positions(s).iter().all(|p| p.is_finite()));
    }
    Ok(sequence.vertex_count())
}

/// A fixture of `tests/data`.
fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn targets() -> Vec<Target> {
    let obj_curves = "# hair\nv 0 0 0\nv 0 1 0\nv 0 2 1\nl 1 2 3\nv 1 0 0\nv 1 1 0\nl -2 -1\n";
    let obj_mesh = "o body\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nf 1//1 3//1 2//1\n\
                    f 1 2 4\nf 1 4 3\nf 2 3 4\n";
    vec![
        Target {
            name: "TressFX 4",
            read: |b, o| checked_curves(read_tfx(b, o)),
            seed: tfx4_bytes(&two_strands()),
            count_fields: &[4, 8, 12],
            min_point_bytes: 16,
        },
        Target {
            name: "TressFX 3",
            read: |b, o| checked_curves(read_tfx(b, o)),
            seed: tfx3_bytes(&two_strands()),
            count_fields: &[4, 8, 144],
            min_point_bytes: 12,
        },
        Target {
            name: "cyHair",
            read: |b, o| checked_curves(read_hair(b, o)),
            seed: write_hair_bytes(&sample_curves()).unwrap(),
            // Not the default segments (16): the seed has a segments array.
            count_fields: &[4, 8, 12, 128],
            min_point_bytes: 12,
        },
        Target {
            name: "USC-HairSalon",
            read: |b, o| checked_curves(read_usc_data(b, o)),
            seed: usc_bytes(&strands_with_empty_roots()),
            count_fields: &[0, 4, 20, 60, 76],
            min_point_bytes: 12,
        },
        Target {
            name: "OBJ polylines",
            read: |b, o| checked_curves(read_obj_curves(b, o)),
            seed: obj_curves.as_bytes().to_vec(),
            count_fields: &[],
            // `l 1 2 1 2 ...` names a vertex in two bytes.
            min_point_bytes: 2,
        },
        Target {
            name: "USD text, animated",
            read: |b, o| checked_curves(read_usda_at(b, 1.5, o)),
            seed: super::usda::animated_writer()
                .to_usda_string()
                .unwrap()
                .into_bytes(),
            count_fields: &[],
            // `(0,0,0)` with its comma.
            min_point_bytes: 6,
        },
        Target {
            name: "USD text, Pixar style",
            read: |b, o| checked_curves(read_usda(b, o)),
            seed: super::usda::PIXAR_STYLE.as_bytes().to_vec(),
            count_fields: &[],
            // A constant width expands to every point, but each point is `(0,0,0)`.
            min_point_bytes: 6,
        },
        Target {
            name: "USD crate curves",
            read: |b, o| checked_curves(read_usdc(b, o)),
            seed: super::usd_crate::crate_curves_bytes(),
            // Offsets vary with the writer: `usd_crate.rs` sets the crate's counts to huge values.
            count_fields: &[],
            // A constant width or an indexed primvar expands, but each point is 12 bytes.
            min_point_bytes: 12,
        },
        Target {
            name: "USD crate mesh",
            read: |b, o| checked_mesh(read_usd_mesh(b, o)),
            seed: super::usd_crate::crate_mesh_bytes(),
            count_fields: &[],
            min_point_bytes: 12,
        },
        Target {
            name: "USD text mesh (openusd)",
            read: |b, o| checked_mesh(read_usd_mesh(b, o)),
            seed: super::usd_crate::text_mesh_bytes(),
            count_fields: &[],
            // `(0,0,0)` with its comma.
            min_point_bytes: 6,
        },
        Target {
            name: "Alembic",
            read: |b, o| checked_curves(alembic_without_panic(b, o)),
            seed: super::alembic::fixture(),
            // The root group's offset, the root group's child count, /plain's P and nVertices
            // sizes, the time samplings' size, /plain's property headers' size and its .geom
            // group's child count (see `make_alembic_fixture.py`; u64 fields, low half set).
            count_fields: &[8, 2802, 40, 136, 2294, 1015, 1126],
            min_point_bytes: 12,
        },
        Target {
            name: "USD text mesh sequence",
            read: |b, o| checked_sequence(read_usd_mesh_sequence(b, o)),
            seed: fixture("mesh_sequence.usda"),
            count_fields: &[],
            min_point_bytes: 6,
        },
        Target {
            name: "USD crate mesh sequence",
            read: |b, o| checked_sequence(read_usd_mesh_sequence(b, o)),
            seed: fixture("mesh_sequence.usdc"),
            count_fields: &[],
            min_point_bytes: 12,
        },
        Target {
            name: "Alembic mesh sequence",
            read: |b, o| checked_sequence(read_alembic_mesh_sequence(b, o)),
            seed: fixture("mesh_sequence.abc"),
            count_fields: &[],
            min_point_bytes: 12,
        },
        Target {
            name: ".tfxmesh",
            read: |b, o| checked_mesh(read_tfxmesh(b, o)),
            seed: TETRAHEDRON.as_bytes().to_vec(),
            count_fields: &[],
            min_point_bytes: 8,
        },
        Target {
            name: "OBJ mesh",
            read: |b, o| checked_mesh(read_obj_mesh(b, o)),
            seed: obj_mesh.as_bytes().to_vec(),
            count_fields: &[],
            // tobj may give a vertex per face corner: `f 1 1 1` is 6 bytes for 3 vertices.
            min_point_bytes: 1,
        },
    ]
}

/// Runs `target` on `bytes` with default and strict options.
fn check(target: &Target, bytes: &[u8]) {
    for options in [ImportOptions::default(), ImportOptions::strict()] {
        match (target.read)(bytes, &options) {
            Ok(points) => assert!(
                points * target.min_point_bytes <= bytes.len(),
                "{}: {points} points from {} bytes",
                target.name,
                bytes.len()
            ),
            Err(error) => {
                assert!(error.to_string().starts_with("<memory>: "), "{error}");
            }
        }
    }
}

/// A change to a valid file.
#[derive(Debug, Clone)]
enum Mutation {
    /// XOR the byte at `at` (modulo the length) with `mask`.
    Flip { at: usize, mask: u8 },
    /// Keep the first `len` bytes (modulo the length + 1).
    Truncate { len: usize },
    /// Set the `u32` at one of the target's count fields (`field` modulo their number).
    Count { field: usize, value: u32 },
    /// Insert `bytes` at `at`.
    Insert { at: usize, bytes: Vec<u8> },
    /// Remove up to `len` bytes from `at`.
    Remove { at: usize, len: usize },
}

fn huge_count() -> impl Strategy<Value = u32> {
    prop_oneof![
        Just(u32::MAX),
        Just(0x8000_0000),
        Just(0x7fff_ffff),
        Just(0x1000_0000),
        Just(0xffff),
        Just(0x1_0000),
        Just(0),
        Just(1),
        any::<u32>(),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<usize>(), 1u8..).prop_map(|(at, mask)| Mutation::Flip { at, mask }),
        1 => any::<usize>().prop_map(|len| Mutation::Truncate { len }),
        2 => (any::<usize>(), huge_count()).prop_map(|(field, value)| Mutation::Count { field, value }),
        1 => (any::<usize>(), vec(any::<u8>(), 1..16)).prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        1 => (any::<usize>(), 1usize..16).prop_map(|(at, len)| Mutation::Remove { at, len }),
    ]
}

fn apply(seed: &[u8], mutations: &[Mutation], count_fields: &[usize]) -> Vec<u8> {
    let mut bytes = seed.to_vec();
    for mutation in mutations {
        match mutation {
            Mutation::Flip { at, mask } => {
                if !bytes.is_empty() {
                    let at = at % bytes.len();
                    bytes[at] ^= mask;
                }
            }
            Mutation::Truncate { len } => bytes.truncate(len % (bytes.len() + 1)),
            Mutation::Count { field, value } => {
                if let Some(&at) = count_fields.get(field % count_fields.len().max(1))
                    && at + 4 <= bytes.len()
                {
                    bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
                }
            }
            Mutation::Insert { at, bytes: new } => {
                let at = at % (bytes.len() + 1);
                bytes.splice(at..at, new.iter().copied());
            }
            Mutation::Remove { at, len } => {
                let at = at % (bytes.len() + 1);
                let end = (at + len).min(bytes.len());
                bytes.drain(at..end);
            }
        }
    }
    bytes
}

fn runner(cases: u32) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 2000,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha))
}

#[test]
fn random_bytes_never_panic() {
    for target in targets() {
        // Pure noise, and noise after the start of a valid file (past the signature or version).
        let strategy = (0..=target.seed.len(), vec(any::<u8>(), 0..600));
        let runs = Cell::new(0);
        runner(RANDOM_CASES)
            .run(&strategy, |(keep, noise)| {
                check(&target, &noise);
                let mut bytes = target.seed[..keep].to_vec();
                bytes.extend(noise);
                check(&target, &bytes);
                runs.set(runs.get() + 1);
                Ok(())
            })
            .unwrap_or_else(|e| panic!("{}: {e}", target.name));
        assert_eq!(runs.get(), RANDOM_CASES);
    }
}

#[test]
fn mutated_files_never_panic() {
    for target in targets() {
        let (runs, errors) = (Cell::new(0), Cell::new(0));
        runner(MUTATED_CASES)
            .run(&vec(mutation(), 1..6), |mutations| {
                let bytes = apply(&target.seed, &mutations, target.count_fields);
                check(&target, &bytes);
                runs.set(runs.get() + 1);
                if (target.read)(&bytes, &ImportOptions::default()).is_err() {
                    errors.set(errors.get() + 1);
                }
                Ok(())
            })
            .unwrap_or_else(|e| panic!("{}: {e}", target.name));
        assert_eq!(runs.get(), MUTATED_CASES);
        // The mutations reach past the first check: some files still read, most do not.
        assert!(
            errors.get() > MUTATED_CASES / 4 && errors.get() < MUTATED_CASES,
            "{}: {} of {} mutated files refused",
            target.name,
            errors.get(),
            MUTATED_CASES
        );
    }
}

#[test]
fn the_seeds_are_valid_files() {
    for target in targets() {
        let points = (target.read)(&target.seed, &ImportOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", target.name));
        assert!(points > 0);
    }
}

#[test]
fn huge_header_counts_are_errors_not_allocations() {
    for target in targets() {
        for (field, &at) in target.count_fields.iter().enumerate() {
            for value in [u32::MAX, 0x8000_0000, 0x7fff_ffff, 0x1000_0000, 0x0100_0000] {
                let mutation = Mutation::Count { field, value };
                let bytes = apply(&target.seed, &[mutation], target.count_fields);
                // An offset field pointing far away, or a count: either way the file is too short.
                let error = (target.read)(&bytes, &ImportOptions::default())
                    .expect_err(&format!("{}, field at byte {at} = {value}", target.name));
                let text = error.to_string();
                assert!(
                    text.contains("truncated")
                        || text.contains("invalid")
                        || text.contains("inconsistent counts"),
                    "{}, field at byte {at} = {value}: {text}",
                    target.name
                );
            }
        }
    }
}

/// Tokens of USD text, to build random files that get past the lexer.
const USDA_TOKENS: &[&str] = &[
    "def",
    "over",
    "class",
    "BasisCurves",
    "Mesh",
    "faceVertexCounts",
    "faceVertexIndices.timeSamples",
    "token[]",
    "xformOpOrder",
    "\"xformOp:translate\"",
    "\"!invert!xformOp:rotateZYX:a\"",
    "\"!resetXformStack!\"",
    "double3",
    "xformOp:translate",
    "xformOp:rotateZYX:a.timeSamples",
    "quatf",
    "xformOp:orient",
    "matrix4d",
    "xformOp:transform",
    "((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))",
    "timeCodesPerSecond",
    "Xform",
    "\"c\"",
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    "=",
    ",",
    ":",
    ";",
    "uniform",
    "token",
    "type",
    "\"linear\"",
    "\"cubic\"",
    "int[]",
    "curveVertexCounts",
    "curveVertexCounts.timeSamples",
    "point3f[]",
    "points",
    "points.timeSamples",
    "float[]",
    "widths",
    "primvars:widths:indices",
    "color3f[]",
    "primvars:displayColor",
    "interpolation",
    "\"uniform\"",
    "\"constant\"",
    "\"vertex\"",
    "upAxis",
    "\"Z\"",
    "metersPerUnit",
    "0.01",
    "0",
    "1",
    "2",
    "3",
    "-1",
    "1e30",
    "nan",
    "-inf",
    "None",
    "(0, 0, 0)",
    "(1, 2, 3)",
    "[2]",
    "[(0, 0, 0), (0, 1, 0)]",
    "rel",
    "</a>",
    "@a.usda@",
    "variantSet",
    "reorder",
    "\n",
    "# comment\n",
    "\"\"\"doc\"\"\"",
];

#[test]
fn usda_token_soup_never_panics() {
    let strategy = (
        vec(0..USDA_TOKENS.len(), 0..120),
        proptest::option::of(-2.0f64..5.0),
    );
    let (runs, read) = (Cell::new(0), Cell::new(0));
    runner(MUTATED_CASES)
        .run(&strategy, |(tokens, time)| {
            let mut text = String::from("#usda 1.0\n");
            // Half the cases start with a valid curves prim head, to reach the attributes, a
            // quarter with a mesh's.
            if tokens.len() % 2 == 0 {
                text.push_str("def BasisCurves \"h\" {\n");
            } else if tokens.len() % 4 == 1 {
                text.push_str("def Mesh \"m\" {\n");
            }
            for &t in &tokens {
                text.push_str(USDA_TOKENS[t]);
                text.push(' ');
            }
            for options in [ImportOptions::default(), ImportOptions::strict()] {
                let result = match time {
                    Some(t) => read_usda_at(text.as_bytes(), t, &options),
                    None => read_usda(text.as_bytes(), &options),
                };
                match checked_curves(result) {
                    Ok(points) => {
                        assert!(points * 6 <= text.len());
                        read.set(read.get() + 1);
                    }
                    Err(error) => assert!(error.to_string().starts_with("<memory>: "), "{error}"),
                }
                let meshes = [
                    checked_mesh(read_usd_mesh(text.as_bytes(), &options)),
                    checked_sequence(read_usd_mesh_sequence(text.as_bytes(), &options)),
                ];
                for result in meshes {
                    match result {
                        Ok(points) => assert!(points * 6 <= text.len()),
                        Err(error) => {
                            assert!(error.to_string().starts_with("<memory>: "), "{error}")
                        }
                    }
                }
            }
            runs.set(runs.get() + 1);
            Ok(())
        })
        .unwrap();
    assert_eq!(runs.get(), MUTATED_CASES);
}

#[test]
fn deeply_nested_usda_prims_are_an_error_not_a_stack_overflow() {
    let text = format!("#usda 1.0\n{}", "def Xform \"x\" {\n".repeat(100_000));
    let error = read_usda(text.as_bytes(), &ImportOptions::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "<memory>: line 202: prims nested deeper than 200 levels"
    );
    let text = format!("#usda 1.0\n(\n a = {}", "[".repeat(100_000));
    let error = read_usda(text.as_bytes(), &ImportOptions::default()).unwrap_err();
    assert!(error.to_string().contains("truncated"), "{error}");
}
