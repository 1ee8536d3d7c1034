//! Timestamp queries of a frame: a pair per timed pass (`frame::Pass`), written at the start
//! and end of its render passes, resolved and read back after the frame.

use std::sync::{Arc, Mutex};

use crate::error::RasterError;
use crate::gpu::Gpu;

/// Timestamp queries of one frame: two per pass, resolved and read back after the frame.
pub(crate) struct Timestamps {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    count: u32,
}

impl Timestamps {
    pub(crate) fn new(device: &wgpu::Device, passes: u32) -> Timestamps {
        let count = 2 * passes;
        let size = 8 * u64::from(count);
        Timestamps {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp read-back"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            count,
        }
    }

    pub(crate) fn writes(&self, pass: u32) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(2 * pass),
            end_of_pass_write_index: Some(2 * pass + 1),
        }
    }

    /// Timing entry `pass` spread over several render passes: its start written by the
    /// first, its end by the last, nothing by those between (wgpu refuses timestamp writes
    /// with neither index).
    pub(crate) fn span_writes(
        &self,
        pass: u32,
        first: bool,
        last: bool,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        (first || last).then(|| wgpu::RenderPassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: first.then_some(2 * pass),
            end_of_pass_write_index: last.then_some(2 * pass + 1),
        })
    }

    pub(crate) fn encode_resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.set, 0..self.count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, self.resolve.size());
    }

    /// Milliseconds of each pass of the last frame.
    pub(crate) fn read(&self, gpu: &Gpu) -> Result<Vec<f64>, RasterError> {
        let slice = self.readback.slice(..);
        let status = Arc::new(Mutex::new(None));
        let s = status.clone();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            *s.lock().unwrap_or_else(|p| p.into_inner()) = Some(r);
        });
        gpu.wait_for("reading timestamps")?;
        if !matches!(
            status.lock().unwrap_or_else(|p| p.into_inner()).take(),
            Some(Ok(()))
        ) {
            return Err(RasterError::Gpu {
                context: "reading timestamps".into(),
                message: "the timestamp buffer could not be mapped".into(),
            });
        }
        let ticks: Vec<u64> = slice
            .get_mapped_range()
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect();
        self.readback.unmap();
        let period_ms = f64::from(gpu.queue.get_timestamp_period()) * 1e-6;
        Ok(ticks
            .chunks_exact(2)
            .map(|p| p[1].saturating_sub(p[0]) as f64 * period_ms)
            .collect())
    }
}
