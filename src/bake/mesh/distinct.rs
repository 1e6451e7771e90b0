//! Exact deduplication before the bake: triangles that must bake to the
//! same states are classified once. Two triangles do when their UVs are
//! equal bit for bit (after every transform the caller applied), their
//! levels are equal, and they are read through the same texture (the same
//! object) with bit-for-bit equal sampler, cutoff and alpha factor, and the
//! same vertex-alpha range (the range, not the alphas, is what the bake
//! reads under nearest filtering and linear filtering by footprint) or,
//! under linear filtering by value, the same vertex alphas (its walk reads
//! the alpha per part). [`Plan`] finds the classes in order of first appearance, so the
//! first-appearance order of the micromaps, and with it every output byte,
//! is what baking each triangle in turn gives.

use super::input::{
    check_vertex_alpha, make_room, push_vertex_ranges, room, Mesh, MeshBakeError, MeshOptions,
};
use crate::bake::alpha_test::{judges_by_value, VertexScale};
use crate::bake::baker::Baker;
use crate::bake::material::{vertex_bound_baker, vertex_range, FactorTexture, VertexBounds};
use crate::bake::mips::mip_bakers;
use crate::bake::mips::Mips;
use crate::bake::parallel::Runner;
use crate::bake::texture::AlphaTexture;
use crate::bake::texture_unit::LinearRule;
use crate::bake::triangle::{TriangleStatus, UvTriangle};
use crate::bake::walk_variants::MAX_VARIANTS;
use crate::micromap::TriangleEntry;
use crate::Level;
use alloc::collections::BTreeMap;
use alloc::vec::Vec;

/// One distinct triangle's bake, as the report and [`super::MeshBake`]
/// keep it (its map is in the buffers' builder).
#[derive(Clone, Copy, Debug)]
pub(super) struct Distinct {
    /// The baked map's level (0 for a special index from the coordinates).
    pub(super) level: Level,
    pub(super) status: TriangleStatus,
    pub(super) counts: [u64; 4],
    /// Unknown micro-triangles the exact model knows ([`crate::bake::BakedTriangle::widened`]).
    pub(super) widened: u64,
    /// Work units its bake spent.
    pub(super) work: u64,
    /// Work spent besides and thrown away ([`BakedTriangle::speculative_work`](crate::bake::BakedTriangle::speculative_work)).
    pub(super) speculative_work: u64,
    pub(super) entry: TriangleEntry,
}

/// One distinct triangle to bake.
pub(super) struct Work {
    /// Index into [`Plan::bakers`].
    pub(super) baker: u32,
    /// Indices into [`Plan::bounds`] of the lower and the upper bound's
    /// bakers when the mesh has vertex alpha.
    pub(super) bound: Option<(u32, u32)>,
    /// The vertex alphas when the mesh has them and its baker reads them
    /// per part (linear filtering by value; `bound` is `None` then).
    pub(super) alphas: Option<[f32; 3]>,
    /// With `alphas`: the first of the distinct triangles with the same
    /// baker, UVs and level and other alphas (at most
    /// [`MAX_VARIANTS`] together), which bakes them all in one walk; `None`
    /// for that first one.
    pub(super) leader: Option<u32>,
    /// For the first one: every one of them, itself first.
    pub(super) members: Vec<u32>,
    pub(super) uv: UvTriangle,
    pub(super) level: Level,
    /// How many input triangles it stands for.
    pub(super) triangles: usize,
}

impl Work {
    /// The cost model: micro-triangles classified (two bakes with vertex
    /// alpha bounds; one walk for a group of variants, about the cost of
    /// two, made by its first).
    pub(super) fn cost(&self) -> u64 {
        let micro = 1u64 << (2 * self.level.get().min(31));
        if self.leader.is_some() {
            1
        } else if self.bound.is_some() || self.members.len() > 1 {
            micro.saturating_mul(2)
        } else {
            micro
        }
    }
}

/// The distinct triangles met so far, by key (baker, vertex-alpha bound,
/// UV bits, level): an open-addressing table of indices into the plan's
/// work list, which holds the keys (a map of keys would hold each twice,
/// and costs more per triangle than the bake of a small one).
#[derive(Default)]
struct FirstSeen {
    /// Indices into the work list, `u32::MAX` for an empty slot; a power
    /// of two long, at most half full.
    slots: Vec<u32>,
}

impl FirstSeen {
    /// The key of a distinct triangle, bit for bit.
    fn key(w: &Work) -> [u32; 14] {
        let uv = w.uv;
        let alphas = w.alphas.unwrap_or_default().map(f32::to_bits);
        [
            w.baker,
            w.bound.map_or(0, |b| b.0 + 1),
            w.bound.map_or(0, |b| b.1 + 1),
            u32::from(w.alphas.is_some()),
            alphas[0],
            alphas[1],
            alphas[2],
            w.level.get(),
            uv[0][0].to_bits(),
            uv[0][1].to_bits(),
            uv[1][0].to_bits(),
            uv[1][1].to_bits(),
            uv[2][0].to_bits(),
            uv[2][1].to_bits(),
        ]
    }

    fn slot(key: &[u32; 14], mask: usize) -> usize {
        let hash = key.iter().fold(0u64, |h, &k| {
            (h.rotate_left(5) ^ u64::from(k)).wrapping_mul(0x517c_c1b7_2722_0a95)
        });
        (hash >> 32) as usize & mask
    }

    /// Where `key` is: `Ok(index in work)`, or `Err(empty slot)` for it.
    fn find(&self, key: &[u32; 14], work: &[Work]) -> Result<u32, usize> {
        let mask = self.slots.len() - 1;
        let mut s = Self::slot(key, mask);
        loop {
            match self.slots[s] {
                u32::MAX => return Err(s),
                id if Self::key(&work[id as usize]) == *key => return Ok(id),
                _ => s = (s + 1) & mask,
            }
        }
    }

    /// The index in `work` of the triangle equal to `w`, pushed first when
    /// it is new; `work` has room for it (no reallocation here), and the
    /// table grows fallibly.
    fn id_of(&mut self, w: Work, work: &mut Vec<Work>) -> Result<u32, MeshBakeError> {
        if 2 * (work.len() + 1) > self.slots.len() {
            let len = (2 * (work.len() + 1)).next_power_of_two().max(16);
            let mut slots = room(len)?;
            slots.resize(len, u32::MAX);
            *self = FirstSeen { slots };
            for (id, old) in work.iter().enumerate() {
                // The keys in `work` are distinct: each finds an empty slot.
                if let Err(s) = self.find(&Self::key(old), work) {
                    self.slots[s] = id as u32;
                }
            }
        }
        Ok(match self.find(&Self::key(&w), work) {
            Ok(id) => id,
            Err(s) => {
                self.slots[s] = work.len() as u32;
                work.push(w);
                self.slots[s]
            }
        })
    }
}

/// Per mesh: its baker, its vertex alphas, and whether the walk reads them
/// per part.
type MeshBaker<'v> = (u32, Option<&'v [[f32; 3]]>, bool);

/// The material as exact bits, with the texture's address, and the range
/// of vertex alphas its walks read per part: what a baker is made from.
type BakerKey = (usize, [u32; 12], Option<[u64; 2]>);

/// The distinct triangles of all meshes and the bakers they need.
pub(super) struct Plan {
    /// One baker per distinct (texture, material).
    pub(super) bakers: Vec<Baker>,
    /// Per baker: the (lower, upper) bound bakers of the mip levels below
    /// 0 that [`MeshOptions::mips`] asks for (empty for [`Mips::Level0`]).
    pub(super) mips: Vec<Vec<(Baker, Baker)>>,
    /// The vertex-alpha bound bakers, each for one (baker, side, bound)
    /// of [`VertexBounds`].
    pub(super) bounds: Vec<Baker>,
    /// The distinct triangles, in order of first appearance.
    pub(super) work: Vec<Work>,
    /// Per mesh, per triangle: its distinct triangle.
    pub(super) of_triangle: Vec<Vec<u32>>,
}

impl Plan {
    /// Groups the triangles of `meshes` (resolved to `triangles`, with
    /// `levels`) and builds each baker once. Fails as the bake would: the
    /// first mesh (in order) whose vertex alpha or texture is refused.
    pub(super) fn new(
        meshes: &[Mesh<'_>],
        triangles: &[impl AsRef<[UvTriangle]>],
        levels: &[Vec<Level>],
        options: &MeshOptions,
        runner: &Runner,
    ) -> Result<Plan, MeshBakeError> {
        let mut plan = Plan {
            bakers: Vec::new(),
            mips: Vec::new(),
            bounds: Vec::new(),
            work: Vec::new(),
            of_triangle: room(meshes.len())?,
        };
        // Candidates by key; equal keys are checked for the same texture
        // object (data pointer and vtable).
        let mut bakers: BTreeMap<BakerKey, Vec<(u32, &dyn AlphaTexture)>> = BTreeMap::new();
        // The range of every vertex alpha read per part, over all meshes:
        // the texel classes of those bakers hold over it, so meshes with
        // the same texture and material share a baker (and their equal
        // UVs a walk) whatever their alphas.
        let by_value =
            |mesh: &Mesh<'_>| judges_by_value(mesh.material.sampler.filter, &options.texture_unit);
        let mut all_alphas: Option<VertexScale> = None;
        for (m, (mesh, triangles)) in meshes.iter().zip(triangles).enumerate() {
            if let Ok(Some(alphas)) = check_vertex_alpha(m, mesh, triangles.as_ref().len()) {
                if by_value(mesh) && !alphas.is_empty() {
                    let v = VertexScale::over_all(alphas);
                    all_alphas = Some(all_alphas.map_or(v, |a| a.union(v)));
                }
            }
        }
        // Pass 1, mesh by mesh in order (so the first refused mesh is the
        // error): each mesh's baker, and per baker the lows and highs of
        // its meshes' vertex-alpha ranges.
        let mut mesh_bakers: Vec<MeshBaker<'_>> = room(meshes.len())?;
        let mut ranges: Vec<(Vec<u64>, Vec<u64>)> = Vec::new();
        for (m, (mesh, triangles)) in meshes.iter().zip(triangles).enumerate() {
            let triangles = triangles.as_ref();
            let vertex_alpha = check_vertex_alpha(m, mesh, triangles.len())?;
            if vertex_alpha.is_some() && options.mips != Mips::Level0 {
                return Err(MeshBakeError::VertexAlpha {
                    mesh: m,
                    message: "vertex alpha with mip levels below 0 is not modelled".into(),
                });
            }
            let material = &mesh.material;
            let texture_error = |error| MeshBakeError::Texture { mesh: m, error };
            // Under linear filtering by value the walk reads the vertex
            // alpha per part, against texel classes that hold over all of
            // the mesh's alphas; otherwise bound bakers (below).
            let per_part = vertex_alpha.filter(|_| by_value(mesh)).and(all_alphas);
            let key = (
                core::ptr::from_ref(mesh.texture).cast::<()>() as usize,
                [
                    material.sampler.filter as u32,
                    material.sampler.address_u as u32,
                    material.sampler.address_v as u32,
                    material.sampler.border_alpha.to_bits(),
                    material.cutoff.alpha().to_bits(),
                    material.cutoff.comparison() as u32,
                    material.alpha_factor.to_bits(),
                    // The transform is the baker's: meshes with different
                    // transforms never share one.
                    material.uv_transform.offset()[0].to_bits(),
                    material.uv_transform.offset()[1].to_bits(),
                    material.uv_transform.rotation().to_bits(),
                    material.uv_transform.scale()[0].to_bits(),
                    material.uv_transform.scale()[1].to_bits(),
                ],
                per_part.map(|v| [v.lo.to_bits(), v.hi.to_bits()]),
            );
            let candidates = bakers.entry(key).or_default();
            let baker = if let Some(&(baker, _)) = candidates
                .iter()
                .find(|(_, texture)| core::ptr::eq(*texture, mesh.texture))
            {
                baker
            } else {
                let factored = FactorTexture {
                    inner: mesh.texture,
                    factor: material.alpha_factor,
                };
                let texture: &dyn AlphaTexture = if material.alpha_factor == 1.0 {
                    mesh.texture
                } else {
                    &factored
                };
                let scale = f64::from(material.alpha_factor);
                let make_for = |unit| {
                    move |texture: &dyn AlphaTexture, sampler| {
                        let test = (sampler, material.cutoff, unit, scale);
                        Ok(
                            Baker::new_on_vertex(texture, test, per_part, u64::MAX, runner)?
                                .with_block_budget(options.block_budget)
                                .with_model(options.model)
                                .with_uv_transform(material.uv_transform),
                        )
                    }
                };
                // The mip levels' bounds hold for linear filtering by
                // footprint (`docs/bake.md`, "Every mip level"): with mip
                // levels below 0, level 0 is judged so too.
                let footprint = options.texture_unit.with_linear_rule(LinearRule::Footprint);
                let unit = if options.mips == Mips::Level0 {
                    options.texture_unit
                } else {
                    footprint
                };
                let baker = make_for(unit)(texture, material.sampler).map_err(texture_error)?;
                let mips = mip_bakers(
                    options.mips,
                    texture,
                    material.sampler,
                    &make_for(footprint),
                )
                .map_err(texture_error)?;
                let id = plan.bakers.len() as u32;
                plan.bakers.push(baker);
                plan.mips.push(mips);
                candidates.push((id, mesh.texture));
                id
            };
            mesh_bakers.push((baker, vertex_alpha, per_part.is_some()));
            if let Some(alphas) = vertex_alpha.filter(|_| per_part.is_none()) {
                ranges.resize_with(ranges.len().max(baker as usize + 1), Default::default);
                push_vertex_ranges(&mut ranges[baker as usize], alphas)?;
            }
        }
        // The bounds each baker's ranges snap to: at most VERTEX_BOUNDS
        // bakers per side, whatever the number of distinct ranges.
        let grids: Vec<VertexBounds> = ranges
            .into_iter()
            .map(|(lows, highs)| VertexBounds::new(lows, highs))
            .collect();
        let mut bound_ids: BTreeMap<(u32, bool, u64), u32> = BTreeMap::new();

        // Pass 2: the distinct triangles.
        let mut seen = FirstSeen::default();
        for (m, ((mesh, triangles), levels)) in meshes.iter().zip(triangles).zip(levels).enumerate()
        {
            let triangles = triangles.as_ref();
            let (baker, vertex_alpha, per_part) = mesh_bakers[m];
            let material = &mesh.material;
            let texture_error = |error| MeshBakeError::Texture { mesh: m, error };
            // The baker of one side's bound `v` (bits) of `baker`, made once.
            let mut bound_baker = |upper: bool, v: u64| -> Result<u32, MeshBakeError> {
                if let Some(&id) = bound_ids.get(&(baker, upper, v)) {
                    return Ok(id);
                }
                let made = vertex_bound_baker(
                    mesh.texture,
                    material,
                    options.texture_unit,
                    (upper, v),
                    runner,
                )
                .map_err(texture_error)?
                .with_block_budget(options.block_budget)
                .with_model(options.model);
                let id = plan.bounds.len() as u32;
                plan.bounds.push(made);
                bound_ids.insert((baker, upper, v), id);
                Ok(id)
            };
            let mut of_triangle = room(triangles.len())?;
            // Room for every triangle of the mesh being new: `id_of`
            // pushes without reallocating.
            make_room(&mut plan.work, triangles.len())?;
            for (t, (uv, &level)) in triangles.iter().zip(levels).enumerate() {
                let (bound, alphas) = match vertex_alpha {
                    None => (None, None),
                    Some(alphas) if per_part => (None, Some(alphas[t])),
                    Some(alphas) => {
                        let (low, high) = grids[baker as usize].snap(vertex_range(alphas[t]));
                        let bound = (bound_baker(false, low)?, bound_baker(true, high)?);
                        (Some(bound), None)
                    }
                };
                let work = Work {
                    baker,
                    bound,
                    alphas,
                    leader: None,
                    members: Vec::new(),
                    uv: *uv,
                    level,
                    triangles: 0,
                };
                let id = seen.id_of(work, &mut plan.work)?;
                plan.work[id as usize].triangles += 1;
                of_triangle.push(id);
            }
            plan.of_triangle.push(of_triangle);
        }
        plan.group_variants()?;
        Ok(plan)
    }

    /// Groups the distinct triangles with vertex alphas read per part by
    /// baker, level and UVs (bit for bit), in order, at most
    /// [`MAX_VARIANTS`] per group: each group's first bakes it.
    fn group_variants(&mut self) -> Result<(), MeshBakeError> {
        let mut groups: BTreeMap<(u32, u32, [u32; 6]), Vec<u32>> = BTreeMap::new();
        for (id, w) in self.work.iter().enumerate() {
            if w.alphas.is_none() {
                continue;
            }
            let uv = w.uv.map(|c| c.map(f32::to_bits));
            let key = (
                w.baker,
                w.level.get(),
                [uv[0][0], uv[0][1], uv[1][0], uv[1][1], uv[2][0], uv[2][1]],
            );
            let members = groups.entry(key).or_default();
            make_room(members, 1)?;
            members.push(id as u32);
        }
        for members in groups.into_values() {
            for group in members.chunks(MAX_VARIANTS) {
                let leader = group[0];
                for &m in &group[1..] {
                    self.work[m as usize].leader = Some(leader);
                }
                let list = &mut self.work[leader as usize].members;
                make_room(list, group.len())?;
                list.extend_from_slice(group);
            }
        }
        Ok(())
    }
}
