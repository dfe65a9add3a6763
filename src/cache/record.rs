//! One frame of a simulation cache ([`FrameRecord`]): what the renderer needs to draw that frame
//! and nothing more (the skeletons gathered to draw, with their node frames, coverages and
//! levels; each character's head pose; the frame's report), in a compact little-endian binary
//! layout with a header (magic, layout version, run fingerprint, frame) and an FNV-1a checksum
//! at the end.
//!
//! Layout, every number little-endian:
//!
//! | bytes | what |
//! |---|---|
//! | 8 | magic `HAIRLODC` |
//! | 4 | layout version ([`RECORD_VERSION`]) |
//! | 16 | the run's fingerprint, 16 hex digits ([`super::run_fingerprint`]) |
//! | 8 | frame |
//! | 8 | payload length `P` |
//! | P | payload (below) |
//! | 8 | FNV-1a of every byte before it |
//!
//! Payload: the report as JSON (u32 length, bytes); head poses (u32 count, each rotation
//! `x y z w` then translation `x y z`, f32); chains (u32 count `C`, `C + 1` u32 offsets, `C` f32
//! coverages, `C` u8 give-way flags, `C` u8 simulated-at levels: 0 own, 1 patch, 2 cluster, 3
//! strand group); nodes (u32 count `N`, then `N` positions, `N` normals, `N` binormals, 3 f32
//! each). Floats are stored as their bits, so a record reads back bit for bit.

use glam::{Quat, Vec3};
use hair_core::{Level, RigidTransform};
use hair_render::ActiveSkeletons;
use hair_render::SkeletonFrame;

use crate::pipeline::{Fnv1a, FrameReport};

/// The first bytes of every record.
pub const RECORD_MAGIC: &[u8; 8] = b"HAIRLODC";

/// The layout version of records; a record of another version is refused, naming it.
pub const RECORD_VERSION: u32 = 1;

/// Bytes of the header before the payload.
const HEADER_BYTES: usize = 8 + 4 + 16 + 8 + 8;

/// One simulated frame, as the renderer draws it.
#[derive(Debug, Clone)]
pub struct FrameRecord {
    /// The frame, from 0.
    pub frame: usize,
    /// The frame's report as the simulation made it (levels, model size, stage times; its
    /// rendering time is the simulation's, 0).
    pub report: FrameReport,
    /// Each character's head pose, in the shot's order (one for a lone character).
    pub head_poses: Vec<RigidTransform>,
    /// The skeletons to draw, on the grooms' chain numbering.
    pub drawn: ActiveSkeletons,
}

/// Why bytes are not a record of the run.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RecordFault {
    /// Not a record, damaged, truncated or of another layout: the reason.
    Broken(String),
    /// A record of another run: its fingerprint.
    Foreign(String),
    /// A record of another frame: its frame.
    OtherFrame(usize),
}

impl FrameRecord {
    /// The record's bytes, for the run whose fingerprint is `fingerprint` (16 hex digits).
    pub(crate) fn encode(&self, fingerprint: &str) -> Vec<u8> {
        let mut bytes = Bytes(Vec::with_capacity(
            HEADER_BYTES + 64 + 40 * self.drawn.node_count() + 8,
        ));
        bytes.0.extend_from_slice(RECORD_MAGIC);
        bytes.u32(RECORD_VERSION);
        let mut print = [b'0'; 16];
        for (slot, byte) in print.iter_mut().zip(fingerprint.bytes()) {
            *slot = byte;
        }
        bytes.0.extend_from_slice(&print);
        bytes.u64(self.frame as u64);
        // The payload's length, filled in once the payload is written after it.
        bytes.u64(0);
        let payload = &mut bytes;
        let report = serde_json::to_vec(&self.report).unwrap_or_default();
        payload.u32(report.len() as u32);
        payload.0.extend_from_slice(&report);
        payload.u32(self.head_poses.len() as u32);
        for pose in &self.head_poses {
            payload.f32s(&pose.rotation.to_array());
            payload.f32s(&pose.translation.to_array());
        }
        let frame = self.drawn.frame();
        payload.u32(frame.chain_count() as u32);
        // `chain_count + 1` offsets, a lone 0 when there are no chains.
        let offsets = if frame.chain_offsets.is_empty() {
            &[0][..]
        } else {
            frame.chain_offsets
        };
        for &offset in offsets {
            payload.u32(offset);
        }
        payload.f32s(frame.chain_coverage);
        payload
            .0
            .extend(frame.chain_gives_way.iter().map(|&g| u8::from(g)));
        payload
            .0
            .extend(frame.chain_simulated_at.iter().map(|level| match level {
                None => 0u8,
                Some(Level::Patch) => 1,
                Some(Level::Cluster) => 2,
                Some(Level::StrandGroup) => 3,
            }));
        payload.u32(frame.node_count() as u32);
        for array in [
            frame.node_positions,
            frame.node_normals,
            frame.node_binormals,
        ] {
            for v in array {
                payload.f32s(&v.to_array());
            }
        }
        let payload_len = (bytes.0.len() - HEADER_BYTES) as u64;
        bytes.0[HEADER_BYTES - 8..HEADER_BYTES].copy_from_slice(&payload_len.to_le_bytes());
        let mut hash = Fnv1a::new();
        hash.write(&bytes.0);
        bytes.u64(hash.value());
        bytes.0
    }

    /// Reads the record of frame `frame` of the run whose fingerprint is `fingerprint` from
    /// `bytes`: refuses bytes that are not a record, a damaged or truncated one, one of another
    /// layout version, run or frame.
    pub(crate) fn decode(
        bytes: &[u8],
        fingerprint: &str,
        frame: usize,
    ) -> Result<FrameRecord, RecordFault> {
        let broken = |why: String| RecordFault::Broken(why);
        if bytes.len() < 8 || &bytes[..8] != RECORD_MAGIC {
            return Err(broken(
                "not a hairlod cache record (no HAIRLODC magic)".into(),
            ));
        }
        let mut header = Reader::new(&bytes[8..], "header");
        let version = header.u32()?;
        if version != RECORD_VERSION {
            return Err(broken(format!(
                "record layout version {version}, this hairlod reads version {RECORD_VERSION}: \
                 simulate the cache again with this version"
            )));
        }
        let print = String::from_utf8_lossy(header.take(16)?).into_owned();
        let recorded_frame = header.u64()? as usize;
        let payload_len = header.u64()?;
        let expected = (HEADER_BYTES as u64)
            .checked_add(payload_len)
            .and_then(|n| n.checked_add(8));
        if expected != Some(bytes.len() as u64) {
            return Err(broken(format!(
                "truncated or padded: {} bytes, the header says {}",
                bytes.len(),
                expected.map_or_else(|| "more than can be".into(), |n| n.to_string())
            )));
        }
        let (body, tail) = bytes.split_at(bytes.len() - 8);
        let mut hash = Fnv1a::new();
        hash.write(body);
        let stored = u64::from_le_bytes(tail.try_into().unwrap_or_default());
        if hash.value() != stored {
            return Err(broken(format!(
                "checksum mismatch (stored {stored:016x}, computed {:016x}): the record is damaged",
                hash.value()
            )));
        }
        if print != fingerprint {
            return Err(RecordFault::Foreign(print));
        }
        if recorded_frame != frame {
            return Err(RecordFault::OtherFrame(recorded_frame));
        }
        let mut payload = Reader::new(&body[HEADER_BYTES..], "payload");
        let report_len = payload.u32()? as usize;
        let report: FrameReport = serde_json::from_slice(payload.take(report_len)?)
            .map_err(|e| broken(format!("its frame report does not read: {e}")))?;
        let poses = payload.count(7 * 4, "head poses")?;
        let mut head_poses = Vec::with_capacity(poses);
        for _ in 0..poses {
            let [x, y, z, w, tx, ty, tz] = payload.f32_array::<7>()?;
            head_poses.push(RigidTransform {
                rotation: Quat::from_xyzw(x, y, z, w),
                translation: Vec3::new(tx, ty, tz),
            });
        }
        let chains = payload.count(4 + 4 + 1 + 1, "chains")?;
        let mut chain_offsets = Vec::with_capacity(chains + 1);
        for _ in 0..=chains {
            chain_offsets.push(payload.u32()?);
        }
        let mut chain_coverage = Vec::with_capacity(chains);
        for _ in 0..chains {
            chain_coverage.push(payload.f32()?);
        }
        let chain_gives_way: Vec<bool> = payload.take(chains)?.iter().map(|&g| g != 0).collect();
        let mut chain_simulated_at = Vec::with_capacity(chains);
        for (chain, &code) in payload.take(chains)?.iter().enumerate() {
            chain_simulated_at.push(match code {
                0 => None,
                1 => Some(Level::Patch),
                2 => Some(Level::Cluster),
                3 => Some(Level::StrandGroup),
                other => {
                    return Err(broken(format!(
                        "chain {chain} is simulated at level code {other} (allowed: 0 to 3)"
                    )));
                }
            });
        }
        let nodes = payload.count(36, "nodes")?;
        let mut arrays = [Vec::new(), Vec::new(), Vec::new()];
        for array in &mut arrays {
            array.reserve(nodes);
            for _ in 0..nodes {
                array.push(Vec3::from_array(payload.f32_array::<3>()?));
            }
        }
        if payload.remaining() != 0 {
            return Err(broken(format!(
                "{} bytes left over after the nodes",
                payload.remaining()
            )));
        }
        let [node_positions, node_normals, node_binormals] = arrays;
        let drawn = ActiveSkeletons::from_frame(&SkeletonFrame {
            chain_offsets: if chains == 0 { &[] } else { &chain_offsets },
            node_positions: &node_positions,
            node_normals: &node_normals,
            node_binormals: &node_binormals,
            chain_coverage: &chain_coverage,
            chain_gives_way: &chain_gives_way,
            chain_simulated_at: &chain_simulated_at,
        })
        .map_err(|e| broken(format!("its skeletons do not check: {e}")))?;
        Ok(FrameRecord {
            frame,
            report,
            head_poses,
            drawn,
        })
    }
}

/// A growing little-endian byte buffer.
#[derive(Default)]
struct Bytes(Vec<u8>);

impl Bytes {
    fn u32(&mut self, value: u32) {
        self.0.extend_from_slice(&value.to_le_bytes());
    }

    fn u64(&mut self, value: u64) {
        self.0.extend_from_slice(&value.to_le_bytes());
    }

    fn f32s(&mut self, values: &[f32]) {
        for value in values {
            self.0.extend_from_slice(&value.to_bits().to_le_bytes());
        }
    }
}

/// Reads little-endian numbers off a slice, every read checked against what is left.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    /// What is being read, for errors.
    part: &'static str,
}

impl<'a> Reader<'a> {
    fn new(bytes: &'a [u8], part: &'static str) -> Self {
        Reader { bytes, at: 0, part }
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], RecordFault> {
        if n > self.remaining() {
            return Err(RecordFault::Broken(format!(
                "its {} ends at byte {} of {}, {n} more were needed",
                self.part,
                self.at,
                self.bytes.len()
            )));
        }
        let slice = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(slice)
    }

    fn u32(&mut self) -> Result<u32, RecordFault> {
        let bytes = self.take(4)?;
        Ok(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
    }

    fn u64(&mut self) -> Result<u64, RecordFault> {
        let mut word = [0u8; 8];
        word.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(word))
    }

    fn f32(&mut self) -> Result<f32, RecordFault> {
        Ok(f32::from_bits(self.u32()?))
    }

    fn f32_array<const K: usize>(&mut self) -> Result<[f32; K], RecordFault> {
        let mut values = [0.0; K];
        for value in &mut values {
            *value = self.f32()?;
        }
        Ok(values)
    }

    /// A u32 count of items of at least `item_bytes` bytes each, refused when the bytes left
    /// cannot hold them (so nothing is allocated for a count the record cannot have).
    fn count(&mut self, item_bytes: usize, what: &str) -> Result<usize, RecordFault> {
        let count = self.u32()? as usize;
        if count.saturating_mul(item_bytes) > self.remaining() {
            return Err(RecordFault::Broken(format!(
                "it counts {count} {what}, more than its {} bytes left can hold",
                self.remaining()
            )));
        }
        Ok(count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hair_core::Frame;

    const PRINT: &str = "0123456789abcdef";

    fn record() -> FrameRecord {
        let mut drawn = ActiveSkeletons::new();
        let positions = [
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(0.1, 0.1, 0.3),
            Vec3::new(0.1 + 1e-7, 0.0, 0.3),
        ];
        let frame = Frame::from_tangent_and_normal(Vec3::NEG_Y, Vec3::Z).unwrap();
        let frames = [frame; 3];
        drawn.push_chain(&positions, &frames).unwrap();
        drawn.push_inactive_chain();
        drawn
            .push_chain_giving_way(&positions[..2], &frames[..2], 0.375)
            .unwrap();
        drawn
            .push_rebuilt_chain(&positions, &frames, 0.5, Level::Patch)
            .unwrap();
        FrameRecord {
            frame: 7,
            report: FrameReport {
                frame: 7,
                time: 7.0 / 30.0,
                sections_at: [1, 2, 3],
                max_stretch: 1.5e-6,
                ..FrameReport::default()
            },
            head_poses: vec![RigidTransform {
                rotation: Quat::from_rotation_y(0.3),
                translation: Vec3::new(0.0, 1e-9, -2.0),
            }],
            drawn,
        }
    }

    #[test]
    fn a_record_reads_back_bit_for_bit() {
        let record = record();
        let bytes = record.encode(PRINT);
        let back = FrameRecord::decode(&bytes, PRINT, 7).unwrap();
        assert_eq!(back.frame, 7);
        assert_eq!(back.report, record.report);
        assert_eq!(back.head_poses, record.head_poses);
        let (a, b) = (record.drawn.frame(), back.drawn.frame());
        assert_eq!(a.chain_offsets, b.chain_offsets);
        assert_eq!(a.chain_coverage, b.chain_coverage);
        assert_eq!(a.chain_gives_way, b.chain_gives_way);
        assert_eq!(a.chain_simulated_at, b.chain_simulated_at);
        let bits = |v: &[Vec3]| -> Vec<u32> {
            v.iter()
                .flat_map(|p| p.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(a.node_positions), bits(b.node_positions));
        assert_eq!(bits(a.node_normals), bits(b.node_normals));
        assert_eq!(bits(a.node_binormals), bits(b.node_binormals));
        // The same record encodes to the same bytes.
        assert_eq!(back.encode(PRINT), bytes);
    }

    #[test]
    fn broken_foreign_and_misplaced_records_are_refused() {
        let bytes = record().encode(PRINT);
        // Every truncation is refused (never a panic), naming what is wrong.
        for cut in [0, 5, 8, 20, HEADER_BYTES, bytes.len() / 2, bytes.len() - 1] {
            match FrameRecord::decode(&bytes[..cut], PRINT, 7) {
                Err(RecordFault::Broken(why)) => assert!(!why.is_empty()),
                other => panic!("a record cut at {cut} bytes read as {other:?}"),
            }
        }
        // A flipped bit in the payload fails the checksum.
        let mut damaged = bytes.clone();
        damaged[HEADER_BYTES + 10] ^= 1;
        match FrameRecord::decode(&damaged, PRINT, 7) {
            Err(RecordFault::Broken(why)) => assert!(why.contains("checksum"), "{why}"),
            other => panic!("a damaged record read as {other:?}"),
        }
        assert_eq!(
            FrameRecord::decode(&bytes, "fedcba9876543210", 7).unwrap_err(),
            RecordFault::Foreign(PRINT.into())
        );
        assert_eq!(
            FrameRecord::decode(&bytes, PRINT, 8).unwrap_err(),
            RecordFault::OtherFrame(7)
        );
        let mut other_version = bytes.clone();
        other_version[8] = 9;
        match FrameRecord::decode(&other_version, PRINT, 7) {
            Err(RecordFault::Broken(why)) => assert!(why.contains("version 9"), "{why}"),
            other => panic!("a record of version 9 read as {other:?}"),
        }
    }

    #[test]
    fn a_count_larger_than_the_record_is_refused_before_allocating() {
        // A record whose node count says 2^32 − 1 nodes, checksum made to match.
        let record = FrameRecord {
            drawn: ActiveSkeletons::new(),
            ..record()
        };
        let mut bytes = record.encode(PRINT);
        let node_count_at = bytes.len() - 8 - 4;
        bytes[node_count_at..node_count_at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        let body = bytes.len() - 8;
        let mut hash = Fnv1a::new();
        hash.write(&bytes[..body]);
        let sum = hash.value().to_le_bytes();
        bytes[body..].copy_from_slice(&sum);
        match FrameRecord::decode(&bytes, PRINT, 7) {
            Err(RecordFault::Broken(why)) => assert!(why.contains("4294967295 nodes"), "{why}"),
            other => panic!("an impossible count read as {other:?}"),
        }
    }
}
