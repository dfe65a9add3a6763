//! The Alembic layer of an Ogawa archive checked before the `ogawa-rs` crate reads it: the root
//! group's six parts, the time samplings, and every object's and compound property's headers.
//! `ogawa-rs` parses these with allocations sized from unchecked `u32` lengths, indexes group
//! children by header counts and asserts on duplicate names; here every length, count and index is
//! checked, so the crate's later reads of the same bytes stay in bounds. The container itself
//! (offsets, sizes, depth) is checked first by [`super::ogawa::check_container`].

use std::collections::HashSet;

use super::binary::{Bytes, u32_at};
use super::error::FormatErrorKind;
use super::ogawa::{DATA_BIT, data_block, group_children, structure};

/// Checks the Alembic layout below the root group at `root` (already walked as a container).
pub(crate) fn check_layout(bytes: &Bytes, root: u64) -> Result<(), FormatErrorKind> {
    let children = group_children(bytes, root)?;
    let kinds = [true, true, false, true, true, true];
    let well_formed = children.len() >= 6
        && kinds
            .iter()
            .zip(&children)
            .all(|(&data, &child)| (child & DATA_BIT != 0) == data);
    if !well_formed {
        return Err(structure(
            "archive",
            format!(
                "the root group has {} children; an Alembic archive's has at least 6: version, \
                 file version, top object, metadata, time samplings, indexed metadata",
                children.len()
            ),
            root,
        ));
    }
    let time_samplings = count_time_samplings(bytes, children[4])?;
    let indexed_meta_data = count_indexed_meta_data(bytes, children[5])?;
    let mut check = Check {
        bytes,
        time_samplings,
        indexed_meta_data,
        seen: HashSet::new(),
    };
    check.object(children[2], "")
}

/// A data child's bytes and where they start.
fn data<'a>(bytes: &Bytes<'a>, child: u64, what: &str) -> Result<(u64, &'a [u8]), FormatErrorKind> {
    data_block(bytes, child)?.ok_or_else(|| {
        structure(
            what,
            "a group where a data block belongs".into(),
            child & !DATA_BIT,
        )
    })
}

/// Reads a buffer front to back; running out is an error at the byte offset in the file.
struct Reader<'a> {
    data: &'a [u8],
    at: usize,
    /// Byte offset of `data` in the file.
    base: u64,
    element: &'a str,
}

impl<'a> Reader<'a> {
    fn done(&self) -> bool {
        self.at >= self.data.len()
    }

    fn offset(&self) -> u64 {
        self.base + self.at as u64
    }

    fn take(&mut self, len: u64, what: &str) -> Result<&'a [u8], FormatErrorKind> {
        let remaining = (self.data.len() - self.at) as u64;
        if len > remaining {
            return Err(structure(
                self.element,
                format!("{what} needs {len} bytes, but only {remaining} remain in its block"),
                self.offset(),
            ));
        }
        let slice = &self.data[self.at..self.at + len as usize];
        self.at += len as usize;
        Ok(slice)
    }

    fn u8(&mut self, what: &str) -> Result<u8, FormatErrorKind> {
        Ok(self.take(1, what)?[0])
    }

    fn u32(&mut self, what: &str) -> Result<u32, FormatErrorKind> {
        Ok(u32_at(self.take(4, what)?, 0))
    }

    /// A `u8`, `u16` or `u32` as the property header's size hint says.
    fn hinted(&mut self, hint: u32, what: &str) -> Result<u32, FormatErrorKind> {
        match hint {
            0 => Ok(u32::from(self.u8(what)?)),
            1 => {
                let b = self.take(2, what)?;
                Ok(u32::from(u16::from_le_bytes([b[0], b[1]])))
            }
            2 => self.u32(what),
            _ => Err(structure(
                self.element,
                format!("size hint {hint} (allowed: 0, 1, 2)"),
                self.offset(),
            )),
        }
    }
}

/// Counts the time samplings, checking each one's sample count against its block.
fn count_time_samplings(bytes: &Bytes, child: u64) -> Result<usize, FormatErrorKind> {
    let (base, block) = data(bytes, child, "time samplings")?;
    let mut reader = Reader {
        data: block,
        at: 0,
        base,
        element: "time samplings",
    };
    let mut count = 0;
    while !reader.done() {
        reader.take(12, "max sample and time per cycle")?;
        let samples = reader.u32("samples per cycle")?;
        reader.take(
            8 * u64::from(samples),
            "the sample times of a time sampling",
        )?;
        count += 1;
    }
    Ok(count)
}

/// Counts the indexed metadata (with `ogawa-rs`'s empty entry 0).
fn count_indexed_meta_data(bytes: &Bytes, child: u64) -> Result<usize, FormatErrorKind> {
    let (base, block) = data(bytes, child, "indexed metadata")?;
    let mut reader = Reader {
        data: block,
        at: 0,
        base,
        element: "indexed metadata",
    };
    let mut count = 1;
    while !reader.done() {
        let len = reader.u8("a metadata length")?;
        reader.take(u64::from(len), "a metadata entry")?;
        count += 1;
    }
    Ok(count)
}

struct Check<'b, 'a> {
    bytes: &'b Bytes<'a>,
    time_samplings: usize,
    indexed_meta_data: usize,
    /// Object and compound groups seen: Alembic never shares one, and a shared one would make
    /// reading the tree exponential.
    seen: HashSet<u64>,
}

impl Check<'_, '_> {
    fn visit(&mut self, group: u64, element: &str) -> Result<(), FormatErrorKind> {
        if group != 0 && !self.seen.insert(group) {
            return Err(structure(
                element,
                "the group is reached twice (Alembic shares no object or property group)".into(),
                group,
            ));
        }
        Ok(())
    }

    /// An object group: its properties, its child headers and its children.
    fn object(&mut self, group: u64, path: &str) -> Result<(), FormatErrorKind> {
        let element = if path.is_empty() { "/" } else { path };
        self.visit(group, element)?;
        let children = group_children(self.bytes, group)?;
        let Some(&last) = children.last() else {
            return Ok(());
        };
        if children[0] & DATA_BIT == 0 {
            self.compound(children[0], &format!("{element} properties"))?;
        }
        if last & DATA_BIT == 0 {
            return Ok(());
        }
        let names = self.object_headers(last, element)?;
        if names.len() + 2 > children.len() {
            return Err(structure(
                element,
                format!(
                    "{} child objects named, but the object's group has {} children",
                    names.len(),
                    children.len()
                ),
                group,
            ));
        }
        for (i, name) in names.iter().enumerate() {
            let child = children[i + 1];
            if child & DATA_BIT == 0 {
                self.object(child, &format!("{path}/{name}"))?;
            }
        }
        Ok(())
    }

    /// The names of an object's children, from its headers block.
    fn object_headers(&self, child: u64, element: &str) -> Result<Vec<String>, FormatErrorKind> {
        let (base, block) = data(self.bytes, child, element)?;
        // The last 32 bytes are hashes; ogawa-rs reads no headers from a block of 32 or less.
        if block.len() <= 32 {
            return Ok(Vec::new());
        }
        let mut reader = Reader {
            data: &block[..block.len() - 32],
            at: 0,
            base,
            element,
        };
        let mut names = Vec::new();
        let mut unique = HashSet::new();
        while !reader.done() {
            let at = reader.offset();
            let len = reader.u32("a child name's length")?;
            let name = String::from_utf8_lossy(reader.take(u64::from(len), "a child name")?);
            let index = reader.u8("a metadata index")?;
            if index == 0xff {
                let len = reader.u32("a metadata length")?;
                reader.take(u64::from(len), "the metadata")?;
            } else if usize::from(index) >= self.indexed_meta_data {
                return Err(structure(
                    element,
                    format!(
                        "child {name:?} has metadata index {index}, but the archive has {}",
                        self.indexed_meta_data
                    ),
                    at,
                ));
            }
            if !unique.insert(name.to_string()) {
                return Err(structure(
                    element,
                    format!("two children are named {name:?}"),
                    at,
                ));
            }
            names.push(name.into_owned());
        }
        Ok(names)
    }

    /// A compound property group: its headers, and its compound sub-properties.
    fn compound(&mut self, group: u64, element: &str) -> Result<(), FormatErrorKind> {
        self.visit(group, element)?;
        let children = group_children(self.bytes, group)?;
        let Some(&last) = children.last() else {
            return Ok(());
        };
        if last & DATA_BIT == 0 {
            return Ok(());
        }
        let headers = self.property_headers(last, element)?;
        if headers.len() + 1 > children.len() {
            return Err(structure(
                element,
                format!(
                    "{} properties named, but the property's group has {} children",
                    headers.len(),
                    children.len()
                ),
                group,
            ));
        }
        for (i, (name, compound)) in headers.iter().enumerate() {
            if *compound && children[i] & DATA_BIT == 0 {
                self.compound(children[i], &format!("{element} {name}"))?;
            }
        }
        Ok(())
    }

    /// The names of a compound's properties and whether each is a compound, from its headers
    /// block, with the checks of the values that `ogawa-rs` computes from them.
    fn property_headers(
        &self,
        child: u64,
        element: &str,
    ) -> Result<Vec<(String, bool)>, FormatErrorKind> {
        let (base, block) = data(self.bytes, child, element)?;
        let mut reader = Reader {
            data: block,
            at: 0,
            base,
            element,
        };
        let mut headers = Vec::new();
        while !reader.done() {
            let at = reader.offset();
            let info = reader.u32("a property's info")?;
            let hint = (info >> 2) & 0x3;
            let compound = info & 0x3 == 0;
            let pod = (info >> 4) & 0xf;
            if !compound {
                let samples = reader.hinted(hint, "a sample count")?;
                if info & 0x200 != 0 {
                    reader.hinted(hint, "the first changed index")?;
                    reader.hinted(hint, "the last changed index")?;
                } else if info & 0x800 == 0 && samples == 0 {
                    return Err(structure(
                        element,
                        "a property with no samples and no changed indices".into(),
                        at,
                    ));
                }
                if info & 0x100 != 0 {
                    let index = reader.hinted(hint, "a time sampling index")?;
                    if index as usize >= self.time_samplings {
                        return Err(structure(
                            element,
                            format!(
                                "time sampling index {index}, but the archive has {}",
                                self.time_samplings
                            ),
                            at,
                        ));
                    }
                } else if self.time_samplings == 0 {
                    return Err(structure(element, "no time sampling".into(), at));
                }
            }
            let len = reader.hinted(hint, "a property name's length")?;
            let name = String::from_utf8_lossy(reader.take(u64::from(len), "a property name")?)
                .into_owned();
            let meta = ((info >> 20) & 0xff) as usize;
            if meta == 0xff {
                let len = reader.hinted(hint, "a metadata length")?;
                if !reader.done() {
                    reader.take(u64::from(len), "the metadata")?;
                }
            } else if meta >= self.indexed_meta_data {
                return Err(structure(
                    element,
                    format!(
                        "property {name:?} has metadata index {meta}, but the archive has {}",
                        self.indexed_meta_data
                    ),
                    at,
                ));
            }
            // The pod types that the reader loads samples of (a boolean sample would reach a
            // `todo!()` in ogawa-rs): uint8 (1) for the curve type and the transform's ops,
            // float64 (11) for its values.
            let wanted = match name.as_str() {
                "curveBasisAndType" | ".ops" => Some((1, "uint8")),
                ".vals" => Some((11, "float64")),
                _ => None,
            };
            if let Some((wanted, type_name)) = wanted
                && (compound || pod != wanted)
            {
                return Err(structure(
                    format!("{element} {name}"),
                    format!("pod type {pod} (allowed: {wanted}, {type_name})"),
                    at,
                ));
            }
            headers.push((name, compound));
        }
        Ok(headers)
    }
}
