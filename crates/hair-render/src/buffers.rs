//! GPU buffers that grow to fit their data and are rewritten in place when it fits.

use crate::error::{Result, invalid};

/// Smallest buffer created [bytes]: bindings must not be empty.
const MIN_BUFFER_BYTES: u64 = 256;

/// Checks that `bytes` of `what` fit one storage binding of at most `max_bytes` (the device's
/// `max_storage_buffer_binding_size`), so that an upload too large for the device is refused
/// with its size before anything is written, rather than failing when the bind group is built.
pub(crate) fn check_binding_size(what: &str, bytes: u64, max_bytes: u64) -> Result<()> {
    if bytes > max_bytes {
        return Err(invalid(format!(
            "{what} take {bytes} bytes, more than the device binds in one storage buffer \
             ({max_bytes} bytes): draw fewer strands, or split the groom"
        )));
    }
    Ok(())
}

/// A buffer that is replaced by a larger one when data no longer fits.
#[derive(Debug)]
pub(crate) struct GrowableBuffer {
    label: &'static str,
    usage: wgpu::BufferUsages,
    buffer: wgpu::Buffer,
}

impl GrowableBuffer {
    /// An empty buffer of [`MIN_BUFFER_BYTES`] with `usage` (plus `COPY_DST`).
    pub fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        GrowableBuffer {
            label,
            usage,
            buffer: create(device, label, usage, MIN_BUFFER_BYTES),
        }
    }

    /// The current buffer.
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// Makes the buffer hold at least `bytes` bytes (contents undefined after a replacement);
    /// returns whether it was replaced.
    pub fn reserve(&mut self, device: &wgpu::Device, bytes: u64) -> bool {
        let replaced = bytes > self.buffer.size();
        if replaced {
            let size = (bytes + bytes / 2)
                .max(MIN_BUFFER_BYTES)
                .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
            self.buffer = create(device, self.label, self.usage, size);
        }
        replaced
    }

    /// Writes `bytes` (a multiple of 4 long) at the start of the buffer, first replacing it with a
    /// larger one (1.5× the need) when it is too small. Returns whether the buffer was replaced,
    /// so that bind groups naming it can be rebuilt.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) -> bool {
        let replaced = self.reserve(device, bytes.len() as u64);
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
        replaced
    }
}

fn create(
    device: &wgpu::Device,
    label: &str,
    usage: wgpu::BufferUsages,
    size: u64,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_binding_over_the_device_limit_is_refused_with_its_size() {
        assert!(check_binding_size("residual profiles", 128, 128).is_ok());
        let error = check_binding_size("residual profiles", 129, 128)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("residual profiles") && error.contains("129") && error.contains("128"),
            "{error}"
        );
    }
}
