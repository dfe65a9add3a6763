//! The static hair items on the GPU (strands, clusters, patches, the strands' residual
//! profiles), their bind groups, and the preparation of a frame's batches over them.

use crate::batches::{Batch, ChainOrder, GpuChain};
use crate::buffers::{GrowableBuffer, check_binding_size};
use crate::device::GpuContext;
use crate::error::{Result, invalid};
use crate::inputs::{GpuStrand, StrandSet, pack_strands};
use crate::pipelines::Pipelines;
use crate::scopes::ErrorScopes;
use crate::strand_shapes::StrandShapes;
use crate::surfaces::{ClusterSet, PatchSet, chain_ring_radii, pack_clusters, pack_patches};
use crate::thinning::{StrandSpan, strand_spans};

/// The three kinds of drawn hair geometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ItemKind {
    Strands,
    Clusters,
    Patches,
}

/// The static items of one kind on the GPU, sorted by chain, and their bind group.
#[derive(Debug)]
struct Items {
    buffer: GrowableBuffer,
    /// Group 1 of the passes drawing these items; `None` after a buffer it names was replaced.
    bind_group: Option<wgpu::BindGroup>,
    order: ChainOrder,
}

impl Items {
    fn new(device: &wgpu::Device, label: &'static str) -> Items {
        Items {
            buffer: GrowableBuffer::new(device, label, wgpu::BufferUsages::STORAGE),
            bind_group: None,
            order: ChainOrder::default(),
        }
    }

    /// Replaces the items: `chains` in input order, `packed` their GPU records in input order.
    fn upload<T: bytemuck::Pod>(&mut self, gpu: &GpuContext, chains: &[u32], packed: &[T]) {
        let order = ChainOrder::new(chains);
        let sorted = order.sorted(packed);
        self.upload_sorted(gpu, order, &sorted);
    }

    /// Replaces the items with `sorted`, their GPU records already in `order`'s sorted order.
    fn upload_sorted<T: bytemuck::Pod>(
        &mut self,
        gpu: &GpuContext,
        order: ChainOrder,
        sorted: &[T],
    ) {
        if self
            .buffer
            .write(&gpu.device, &gpu.queue, bytemuck::cast_slice(sorted))
        {
            self.bind_group = None;
        }
        self.order = order;
    }
}

/// A frame's draws, prepared before any pass begins: each kind's bind group (group 1) and
/// batches (strands in chain order, clusters and patches nearest first).
#[derive(Debug)]
pub(crate) struct PreparedItems {
    /// Group 1 of strands, clusters and patches.
    pub groups: [wgpu::BindGroup; 3],
    /// The batches of strands, clusters and patches.
    pub batches: [Vec<Batch>; 3],
}

/// Every static item of the renderer, with what a frame's batching reads from them.
#[derive(Debug)]
pub(crate) struct HairItems {
    strands: Items,
    clusters: Items,
    patches: Items,
    /// The strands' residual profiles (`vec4` per entry, [`hair_core::PROFILE_SAMPLES`] per
    /// profile; binding 2 of the strand items).
    strand_profiles: GrowableBuffer,
    /// The strands this frame draws, by sorted position (binding 3 of the strand items).
    drawn_strands: GrowableBuffer,
    /// Each strand's shift [m] (`vec4`, w unused) by sorted position (binding 4 of the strand
    /// items): zeros unless [`HairItems::set_strand_root_shifts`] set some.
    strand_shifts: GrowableBuffer,
    /// Whether `strand_shifts` holds shifts (not all zeros).
    shifted: bool,
    /// Sorted-order scratch of the shifts.
    shift_scratch: Vec<[f32; 4]>,
    /// Largest cluster ring radius [m] per chain (0 without clusters), from the cluster upload.
    chain_ring_radii: Vec<f32>,
    /// Strand count and width per chain, from the strand upload (for strand thinning).
    chain_strand_spans: Vec<StrandSpan>,
    /// This frame's list for `drawn_strands`.
    drawn_scratch: Vec<u32>,
    /// Draw-order scratch of the front-to-back surface batches.
    order_scratch: Vec<(f32, u32)>,
}

impl HairItems {
    /// No items yet.
    pub fn new(device: &wgpu::Device) -> HairItems {
        let storage = wgpu::BufferUsages::STORAGE;
        HairItems {
            strands: Items::new(device, "hair-render strands"),
            clusters: Items::new(device, "hair-render clusters"),
            patches: Items::new(device, "hair-render patches"),
            strand_profiles: GrowableBuffer::new(device, "hair-render strand profiles", storage),
            drawn_strands: GrowableBuffer::new(device, "hair-render drawn strands", storage),
            strand_shifts: GrowableBuffer::new(device, "hair-render strand shifts", storage),
            shifted: false,
            shift_scratch: Vec::new(),
            chain_ring_radii: Vec::new(),
            chain_strand_spans: Vec::new(),
            drawn_scratch: Vec::new(),
            order_scratch: Vec::new(),
        }
    }

    /// Number of uploaded items of `kind`.
    pub fn count(&self, kind: ItemKind) -> usize {
        self.items(kind).order.item_count()
    }

    /// The strands' order (sorted by chain).
    pub fn strand_order(&self) -> &ChainOrder {
        &self.strands.order
    }

    /// Largest cluster ring radius [m] per chain.
    pub fn chain_ring_radii(&self) -> &[f32] {
        &self.chain_ring_radii
    }

    /// Strand count and width per chain.
    pub fn chain_strand_spans(&self) -> &[StrandSpan] {
        &self.chain_strand_spans
    }

    fn items(&self, kind: ItemKind) -> &Items {
        match kind {
            ItemKind::Strands => &self.strands,
            ItemKind::Clusters => &self.clusters,
            ItemKind::Patches => &self.patches,
        }
    }

    /// Checks that a frame of `chains` chains has every chain the items follow.
    pub fn check_chains(&self, chains: u32) -> Result<()> {
        for (what, items) in [
            ("strands", &self.strands),
            ("clusters", &self.clusters),
            ("patches", &self.patches),
        ] {
            let needed = items.order.chains_needed();
            if needed > chains {
                return Err(crate::error::invalid(format!(
                    "the {what} follow chains up to {} but the frame has {chains} chains",
                    needed - 1
                )));
            }
        }
        Ok(())
    }

    /// Uploads the static strand data with per-strand lengths and tip scales, replacing any
    /// earlier set.
    pub fn upload_strands(
        &mut self,
        gpu: &GpuContext,
        strands: &StrandSet<'_>,
        shapes: &StrandShapes<'_>,
    ) -> Result<()> {
        strands.validate()?;
        shapes.validate(strands.strand_count())?;
        let max_bytes = gpu.device.limits().max_storage_buffer_binding_size;
        let strand_bytes = std::mem::size_of::<GpuStrand>() as u64;
        check_binding_size(
            "strands",
            strands.strand_count() as u64 * strand_bytes,
            max_bytes,
        )?;
        // Profiles go up as vec4<f32>: 16 bytes an entry.
        check_binding_size(
            "residual profiles",
            shapes.profiles.len() as u64 * 16,
            max_bytes,
        )?;
        // Ranked within each chain, so that a dissolving chain draws only the strands it shows.
        let order = ChainOrder::with_dissolve_ranks(strands.strand_chain);
        let mut sorted = order.sorted(&pack_strands(strands, shapes));
        for (strand, &rank) in sorted.iter_mut().zip(&order.ranks) {
            strand.dissolve_rank = rank;
        }
        let scope = ErrorScopes::push(&gpu.device);
        self.strands.upload_sorted(gpu, order, &sorted);
        self.chain_strand_spans = strand_spans(strands);
        let profiles: Vec<[f32; 4]> = shapes
            .profiles
            .iter()
            .map(|r| r.extend(0.0).to_array())
            .collect();
        if self
            .strand_profiles
            .write(&gpu.device, &gpu.queue, bytemuck::cast_slice(&profiles))
        {
            self.strands.bind_group = None;
        }
        self.write_zero_shifts(gpu);
        scope.pop("uploading strands")
    }

    /// Moves each uploaded strand by `shifts[s]` [m, world] in the frames drawn from now on
    /// (`shifts` in upload order, one per strand), or by nothing when `shifts` is empty. The
    /// whole strand moves, so a strand whose root is carried somewhere its skeleton's rest
    /// offsets do not put it (a stretching skin) is drawn from there. Refuses a count that is
    /// not the strand count and a shift that is not finite; the shifts set before stay.
    pub fn set_strand_root_shifts(
        &mut self,
        gpu: &GpuContext,
        shifts: &[glam::Vec3],
    ) -> Result<()> {
        if shifts.is_empty() {
            if self.shifted {
                self.write_zero_shifts(gpu);
            }
            return Ok(());
        }
        let strands = self.strands.order.item_count();
        if shifts.len() != strands {
            return Err(invalid(format!(
                "{} strand root shifts for {strands} uploaded strands",
                shifts.len()
            )));
        }
        if let Some(strand) = shifts.iter().position(|s| !s.is_finite()) {
            return Err(invalid(format!(
                "strand {strand}'s root shift {} is not finite",
                shifts[strand]
            )));
        }
        self.shift_scratch.clear();
        self.shift_scratch.extend(
            self.strands
                .order
                .sorted_to_input
                .iter()
                .map(|&i| shifts[i as usize].extend(0.0).to_array()),
        );
        let scope = ErrorScopes::push(&gpu.device);
        if self.strand_shifts.write(
            &gpu.device,
            &gpu.queue,
            bytemuck::cast_slice(&self.shift_scratch),
        ) {
            self.strands.bind_group = None;
        }
        self.shifted = true;
        scope.pop("uploading strand root shifts")
    }

    /// Whether the strands are drawn shifted ([`HairItems::set_strand_root_shifts`]).
    pub fn strands_shifted(&self) -> bool {
        self.shifted
    }

    /// Zero shifts for every uploaded strand.
    fn write_zero_shifts(&mut self, gpu: &GpuContext) {
        self.shift_scratch.clear();
        self.shift_scratch
            .resize(self.strands.order.item_count(), [0.0; 4]);
        if self.strand_shifts.write(
            &gpu.device,
            &gpu.queue,
            bytemuck::cast_slice(&self.shift_scratch),
        ) {
            self.strands.bind_group = None;
        }
        self.shifted = false;
    }

    /// Uploads the static cluster data, replacing any earlier set.
    pub fn upload_clusters(&mut self, gpu: &GpuContext, clusters: &ClusterSet<'_>) -> Result<()> {
        clusters.validate()?;
        let packed = pack_clusters(clusters);
        let scope = ErrorScopes::push(&gpu.device);
        self.clusters.upload(gpu, clusters.cluster_chain, &packed);
        self.chain_ring_radii = chain_ring_radii(clusters);
        scope.pop("uploading clusters")
    }

    /// Uploads the static patch data, replacing any earlier set.
    pub fn upload_patches(&mut self, gpu: &GpuContext, patches: &PatchSet<'_>) -> Result<()> {
        patches.validate()?;
        let packed = pack_patches(patches);
        let scope = ErrorScopes::push(&gpu.device);
        self.patches.upload(gpu, patches.patch_chain, &packed);
        scope.pop("uploading patches")
    }

    /// Forgets the strands' bind group, which names the chain-curve samples buffer just replaced.
    pub fn chain_samples_replaced(&mut self) {
        self.strands.bind_group = None;
    }

    /// Group 1 of `kind` (the strands' also binds `chain_samples`, the chain-curve pass's output).
    pub fn bind_group(
        &mut self,
        kind: ItemKind,
        device: &wgpu::Device,
        pipelines: &Pipelines,
        chain_samples: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let items = match kind {
            ItemKind::Strands => &mut self.strands,
            ItemKind::Clusters => &mut self.clusters,
            ItemKind::Patches => &mut self.patches,
        };
        if let Some(group) = &items.bind_group {
            return group.clone();
        }
        let items_entry = wgpu::BindGroupEntry {
            binding: 0,
            resource: items.buffer.buffer().as_entire_binding(),
        };
        let group = if kind == ItemKind::Strands {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hair-render strand items"),
                layout: &pipelines.strand_items_layout,
                entries: &[
                    items_entry,
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: chain_samples.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: self.strand_profiles.buffer().as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: self.drawn_strands.buffer().as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: self.strand_shifts.buffer().as_entire_binding(),
                    },
                ],
            })
        } else {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hair-render items"),
                layout: &pipelines.items_layout,
                entries: &[items_entry],
            })
        };
        items.bind_group = Some(group.clone());
        group
    }

    /// Builds this frame's batches over `chain_table` (chains at `chain_distances` [m] from the
    /// camera), uploads the list of the strands drawn, and gathers the bind groups.
    pub fn prepare(
        &mut self,
        gpu: &GpuContext,
        pipelines: &Pipelines,
        chain_samples: &wgpu::Buffer,
        chain_table: &[GpuChain],
        chain_distances: &[f32],
    ) -> PreparedItems {
        // Strands in chain order over the list of the strands drawn (few draws, thinned and
        // dissolving chains included); clusters and patches nearest first, so that early depth
        // testing skips the hidden surfaces' shading.
        let mut batches: [Vec<Batch>; 3] = Default::default();
        self.strands
            .order
            .listed_batches(chain_table, &mut self.drawn_scratch, &mut batches[0]);
        if self.drawn_strands.write(
            &gpu.device,
            &gpu.queue,
            bytemuck::cast_slice(&self.drawn_scratch),
        ) {
            self.strands.bind_group = None;
        }
        let device = &gpu.device;
        let groups = [ItemKind::Strands, ItemKind::Clusters, ItemKind::Patches]
            .map(|kind| self.bind_group(kind, device, pipelines, chain_samples));
        for (items, out) in [&self.clusters, &self.patches]
            .into_iter()
            .zip(&mut batches[1..])
        {
            items.order.batches_front_to_back(
                chain_table,
                chain_distances,
                &mut self.order_scratch,
                out,
            );
        }
        PreparedItems { groups, batches }
    }
}
