//! What a frame traces: the scene (meshes of triangles with positions and
//! UVs, their textures and materials, and the transforms that place each
//! mesh in the world) and the micromaps for its triangles.

use crate::error::{RenderError, SceneError};
use micromap_index::bake::mesh::Material;
use micromap_index::bake::{AddressMode, Comparison, Filter, UvTriangle};
use micromap_index::micromap::{
    read_buffers, BufferBytes, IndexWidth, MicromapBuffers, MicromapIndex, ReadBuffers, ReadOptions,
};
use std::collections::BTreeMap;
use std::ops::Range;

/// The identity transform, row-major 3x4.
pub const IDENTITY_TRANSFORM: [f32; 12] =
    [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// Most instances of all meshes together.
pub const MAX_INSTANCES: usize = 1 << 20;

/// An alpha texture as the shader reads it: binary32 alphas, row-major,
/// row 0 at `v = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneTexture {
    /// Texels per row (at least 1).
    pub width: u32,
    /// Rows (at least 1).
    pub height: u32,
    /// `width * height` alphas.
    pub alphas: Vec<f32>,
}

/// A material: which texture, and how it is alpha-tested.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneMesh {
    /// Index into the scene's textures.
    pub texture: usize,
    /// Sampler, cutoff and alpha factor, as the bake took them.
    pub material: Material,
}

/// Alpha-masked triangles to trace.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    textures: Vec<SceneTexture>,
    meshes: Vec<SceneMesh>,
    /// Per mesh: its first triangle.
    first: Vec<u32>,
    /// Per mesh: its row-major 3x4 object-to-world transforms.
    instances: Vec<Vec<[f32; 12]>>,
    positions: Vec<[[f32; 3]; 3]>,
    uvs: Vec<UvTriangle>,
    /// Per triangle: its vertices' alphas (glTF's `COLOR_0` alpha; 1 for
    /// a mesh without).
    vertex_alpha: Vec<[f32; 3]>,
    /// Per mesh: whether it has vertex alpha (the shader multiplies it in).
    has_vertex_alpha: Vec<bool>,
    mesh_of: Vec<u32>,
}

impl Scene {
    /// An empty scene over `textures`.
    #[must_use]
    pub fn new(textures: Vec<SceneTexture>) -> Scene {
        Scene {
            textures,
            meshes: Vec::new(),
            first: Vec::new(),
            instances: Vec::new(),
            positions: Vec::new(),
            uvs: Vec::new(),
            vertex_alpha: Vec::new(),
            has_vertex_alpha: Vec::new(),
            mesh_of: Vec::new(),
        }
    }

    /// Adds a mesh drawn once where its positions are
    /// ([`add_placed_mesh`](Self::add_placed_mesh) with [`IDENTITY_TRANSFORM`]).
    pub fn add_mesh(
        &mut self,
        mesh: SceneMesh,
        positions: &[[[f32; 3]; 3]],
        uvs: &[UvTriangle],
    ) -> Result<(), RenderError> {
        self.add_placed_mesh(mesh, positions, uvs, &[IDENTITY_TRANSFORM])
    }

    /// Adds a mesh: its material and triangles (positions and UVs, in the
    /// order the micromaps' index buffer follows), drawn once per transform
    /// of `instances` (row-major 3x4 object-to-world; none: not drawn).
    /// Refused: a texture that does not exist or has not `width * height`
    /// alphas, lists of different lengths, a position, UV or transform
    /// that is not finite, more than 2^24 triangles or [`MAX_INSTANCES`]
    /// instances in all.
    pub fn add_placed_mesh(
        &mut self,
        mesh: SceneMesh,
        positions: &[[[f32; 3]; 3]],
        uvs: &[UvTriangle],
        instances: &[[f32; 12]],
    ) -> Result<(), RenderError> {
        self.add_placed_mesh_with_vertex_alpha(mesh, positions, uvs, None, instances)
    }

    /// [`add_placed_mesh`](Self::add_placed_mesh) with the alphas of each
    /// triangle's vertices (glTF's `COLOR_0` alpha, one entry per
    /// triangle, each in `[0, 1]`), which the shader interpolates in
    /// binary32 (`w a0 + b1 a1 + b2 a2`, `w = 1 - b1 - b2`) and multiplies
    /// into the alpha it tests, after the alpha factor (as a glTF
    /// renderer's `texture * baseColorFactor * COLOR_0`). Refused besides:
    /// a list of another length, or an alpha outside `[0, 1]`.
    pub fn add_placed_mesh_with_vertex_alpha(
        &mut self,
        mesh: SceneMesh,
        positions: &[[[f32; 3]; 3]],
        uvs: &[UvTriangle],
        vertex_alpha: Option<&[[f32; 3]]>,
        instances: &[[f32; 12]],
    ) -> Result<(), RenderError> {
        let mesh_number = self.meshes.len();
        if let Some(alphas) = vertex_alpha {
            if alphas.len() != uvs.len() {
                return Err(SceneError::VertexAlphaLength {
                    mesh: mesh_number,
                    vertex_alpha: alphas.len(),
                    uvs: uvs.len(),
                }
                .into());
            }
            if let Some(triangle) = alphas
                .iter()
                .position(|a| a.iter().any(|x| !(0.0..=1.0).contains(x)))
            {
                return Err(SceneError::VertexAlpha {
                    mesh: mesh_number,
                    triangle,
                }
                .into());
            }
        }
        let Some(t) = self.textures.get(mesh.texture) else {
            return Err(SceneError::NoTexture {
                mesh: mesh_number,
                texture: mesh.texture,
            }
            .into());
        };
        if t.width == 0
            || t.height == 0
            || t.alphas.len() as u64 != u64::from(t.width) * u64::from(t.height)
        {
            return Err(SceneError::TextureSize {
                texture: mesh.texture,
                alphas: t.alphas.len(),
                width: t.width,
                height: t.height,
            }
            .into());
        }
        if positions.len() != uvs.len() {
            return Err(SceneError::Lengths {
                mesh: mesh_number,
                positions: positions.len(),
                uvs: uvs.len(),
            }
            .into());
        }
        if let Some(triangle) = (0..uvs.len()).find(|&i| {
            positions[i].iter().flatten().any(|x| !x.is_finite())
                || uvs[i].iter().flatten().any(|x| !x.is_finite())
        }) {
            return Err(SceneError::NotFinite {
                mesh: mesh_number,
                triangle,
            }
            .into());
        }
        if self.uvs.len() + uvs.len() > (1 << 24) {
            return Err(SceneError::TooManyTriangles.into());
        }
        if let Some(instance) = instances
            .iter()
            .position(|t| t.iter().any(|x| !x.is_finite()))
        {
            return Err(SceneError::Transform {
                mesh: mesh_number,
                instance,
            }
            .into());
        }
        if self.instances.iter().map(Vec::len).sum::<usize>() + instances.len() > MAX_INSTANCES {
            return Err(SceneError::TooManyInstances.into());
        }
        let m = self.meshes.len() as u32;
        self.meshes.push(mesh);
        self.first.push(self.uvs.len() as u32);
        self.instances.push(instances.to_vec());
        self.positions.extend_from_slice(positions);
        self.uvs.extend_from_slice(uvs);
        match vertex_alpha {
            Some(alphas) => self.vertex_alpha.extend_from_slice(alphas),
            None => self
                .vertex_alpha
                .extend(std::iter::repeat([1.0; 3]).take(uvs.len())),
        }
        self.has_vertex_alpha.push(vertex_alpha.is_some());
        self.mesh_of.extend(std::iter::repeat(m).take(uvs.len()));
        Ok(())
    }

    /// Triangles in all meshes.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.uvs.len()
    }

    /// Every triangle's positions.
    #[must_use]
    pub fn positions(&self) -> &[[[f32; 3]; 3]] {
        &self.positions
    }

    /// Every triangle's UVs.
    #[must_use]
    pub fn uvs(&self) -> &[UvTriangle] {
        &self.uvs
    }

    /// Meshes.
    #[must_use]
    pub fn mesh_count(&self) -> usize {
        self.meshes.len()
    }

    /// Mesh `m`'s triangles, in the scene's order.
    #[must_use]
    pub fn mesh_triangles(&self, m: usize) -> Range<usize> {
        let start = self.first.get(m).map_or(self.uvs.len(), |&f| f as usize);
        let end = self
            .first
            .get(m + 1)
            .map_or(self.uvs.len(), |&f| f as usize);
        start..end.max(start)
    }

    /// Mesh `m`'s transforms (row-major 3x4 object-to-world).
    #[must_use]
    pub fn instances(&self, m: usize) -> &[[f32; 12]] {
        self.instances.get(m).map_or(&[], Vec::as_slice)
    }

    /// Every triangle of every drawn instance, in world space (each
    /// product in binary64, rounded once).
    #[must_use]
    pub fn world_triangles(&self) -> Vec<[[f32; 3]; 3]> {
        let mut triangles = Vec::new();
        for m in 0..self.meshes.len() {
            for t in self.instances(m) {
                let place = |p: [f32; 3]| {
                    [0, 1, 2].map(|r| {
                        let row = &t[4 * r..4 * r + 4];
                        (f64::from(row[0]) * f64::from(p[0])
                            + f64::from(row[1]) * f64::from(p[1])
                            + f64::from(row[2]) * f64::from(p[2])
                            + f64::from(row[3])) as f32
                    })
                };
                triangles.extend(
                    self.positions[self.mesh_triangles(m)]
                        .iter()
                        .map(|tri| tri.map(place)),
                );
            }
        }
        triangles
    }

    /// The mesh of triangle `t`.
    #[must_use]
    pub fn mesh_of(&self, t: usize) -> Option<&SceneMesh> {
        self.mesh_of.get(t).map(|&m| &self.meshes[m as usize])
    }

    /// Texture `i`.
    #[must_use]
    pub fn texture(&self, i: usize) -> Option<&SceneTexture> {
        self.textures.get(i)
    }

    /// The box around every drawn vertex in world space (`None` without
    /// one).
    #[must_use]
    pub fn bounds(&self) -> Option<[[f32; 3]; 2]> {
        let world = self.world_triangles();
        let mut points = world.iter().flatten();
        let first = *points.next()?;
        Some(points.fold([first, first], |[lo, hi], p| {
            [
                [0, 1, 2].map(|i| lo[i].min(p[i])),
                [0, 1, 2].map(|i| hi[i].max(p[i])),
            ]
        }))
    }

    /// The meshes, in the order they were added.
    pub(crate) fn meshes(&self) -> &[SceneMesh] {
        &self.meshes
    }

    /// The textures.
    pub(crate) fn textures(&self) -> &[SceneTexture] {
        &self.textures
    }

    /// The shader's `tri_uv` (`TRI_WORDS` floats per triangle): its
    /// three UVs, then its three vertex alphas.
    pub(crate) fn triangle_bytes(&self) -> Vec<u8> {
        self.uvs
            .iter()
            .zip(&self.vertex_alpha)
            .flat_map(|(uv, alpha)| uv.iter().flatten().chain(alpha).copied())
            .flat_map(f32::to_le_bytes)
            .collect()
    }

    /// Triangle `t`'s vertex alphas, if its mesh has vertex alpha.
    #[must_use]
    pub fn vertex_alpha(&self, t: usize) -> Option<[f32; 3]> {
        let m = *self.mesh_of.get(t)? as usize;
        self.has_vertex_alpha[m].then(|| self.vertex_alpha[t])
    }

    pub(crate) fn mesh_of_bytes(&self) -> Vec<u8> {
        self.mesh_of.iter().flat_map(|m| m.to_le_bytes()).collect()
    }

    /// The shader's `mesh_info` (`MESH_WORDS` words per mesh).
    pub(crate) fn mesh_info_bytes(&self) -> Vec<u8> {
        let mut bases = Vec::new();
        let mut base = 0u32;
        for t in &self.textures {
            bases.push(base);
            base = base.saturating_add(t.alphas.len() as u32);
        }
        let address = |a: AddressMode| match a {
            AddressMode::Repeat => 0u32,
            AddressMode::MirroredRepeat => 1,
            AddressMode::ClampToEdge => 2,
            AddressMode::ClampToBorder => 3,
            AddressMode::MirrorClampToEdge => 4,
        };
        let mut words = Vec::new();
        for (mesh_number, m) in self.meshes.iter().enumerate() {
            let t = &self.textures[m.texture];
            let s = m.material.sampler;
            words.extend([
                bases[m.texture],
                t.width,
                t.height,
                u32::from(s.filter == Filter::Linear),
                address(s.address_u),
                address(s.address_v),
                m.material.cutoff.alpha().to_bits(),
                u32::from(m.material.cutoff.comparison() == Comparison::Above),
                m.material.alpha_factor.to_bits(),
                s.border_alpha.to_bits(),
                u32::from(self.has_vertex_alpha[mesh_number]),
            ]);
        }
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    pub(crate) fn texel_bytes(&self) -> Vec<u8> {
        self.textures
            .iter()
            .flat_map(|t| t.alphas.iter())
            .flat_map(|a| a.to_le_bytes())
            .collect()
    }
}

/// How some triangles' micromaps are made ([`Micromaps::level_counts`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LevelCounts {
    /// Triangles per (level, states) of their micromap.
    pub levels: BTreeMap<(u32, u32), u64>,
    /// Triangles with a special index (one state for the whole triangle).
    pub special: u64,
}

/// A micromap array and one index per scene triangle, as `micromap-index
/// bake` writes them (`micromap-data.bin`, `micromap-triangles.bin`,
/// `micromap-indices.bin`), checked once on the host.
#[derive(Clone, Debug)]
pub struct Micromaps {
    data: Vec<u8>,
    records: Vec<u8>,
    indices: Vec<u8>,
    width: IndexWidth,
    read: ReadBuffers,
}

impl Micromaps {
    /// From the files' bytes: checked as `micromap::read_buffers` checks
    /// them (levels up to 12, no overlap), usage counts not required.
    pub fn from_bytes(
        data: Vec<u8>,
        records: Vec<u8>,
        indices: Vec<u8>,
        width: IndexWidth,
    ) -> Result<Micromaps, RenderError> {
        let read = read_buffers(
            &BufferBytes {
                records: &records,
                data: &data,
                usage_counts: None,
                indices: Some((&indices, width)),
            },
            &ReadOptions {
                max_level: 12,
                ..ReadOptions::default()
            },
        )
        .map_err(RenderError::Micromaps)?;
        Ok(Micromaps {
            data,
            records,
            indices,
            width,
            read,
        })
    }

    /// From a bake's buffers (all geometries' indices in order).
    pub fn from_buffers(buffers: &MicromapBuffers) -> Result<Micromaps, RenderError> {
        let mut indices = Vec::new();
        for g in 0..buffers.geometry_count() {
            indices.extend(
                buffers
                    .index_bytes(g, IndexWidth::U32)
                    .map_err(RenderError::MicromapBuffers)?,
            );
        }
        Micromaps::from_bytes(
            buffers.data().to_vec(),
            buffers.records_le_bytes(),
            indices,
            IndexWidth::U32,
        )
    }

    /// The records, micromaps and indices as the library read them.
    #[must_use]
    pub fn read(&self) -> &ReadBuffers {
        &self.read
    }

    pub(crate) fn data(&self) -> &[u8] {
        &self.data
    }

    pub(crate) fn records(&self) -> &[u8] {
        &self.records
    }

    pub(crate) fn indices(&self) -> &[u8] {
        &self.indices
    }

    pub(crate) fn index_width_bytes(&self) -> u32 {
        match self.width {
            IndexWidth::U8 => 1,
            IndexWidth::U16 => 2,
            IndexWidth::U32 => 4,
        }
    }

    /// How the micromaps of `triangles` (scene order) are made: triangles
    /// per (level, states) and with a special index.
    #[must_use]
    pub fn level_counts(&self, triangles: Range<usize>) -> LevelCounts {
        let mut counts = LevelCounts::default();
        let indices = self.read.indices.as_deref().unwrap_or_default();
        for index in indices.get(triangles).unwrap_or_default() {
            match *index {
                MicromapIndex::Record(r) => {
                    if let Some(map) = self.read.micromaps.get(r as usize) {
                        *counts
                            .levels
                            .entry((map.level().get(), map.format().states()))
                            .or_insert(0) += 1;
                    }
                }
                MicromapIndex::Special(_) => counts.special += 1,
            }
        }
        counts
    }

    /// Records per (level, states), over the whole array.
    #[must_use]
    pub fn record_counts(&self) -> BTreeMap<(u32, u32), u64> {
        let mut counts = BTreeMap::new();
        for map in &self.read.micromaps {
            *counts
                .entry((map.level().get(), map.format().states()))
                .or_insert(0) += 1;
        }
        counts
    }

    /// One index per scene triangle.
    pub(crate) fn check_for(&self, scene: &Scene) -> Result<(), RenderError> {
        let n = self.read.indices.as_ref().map_or(0, Vec::len);
        if n != scene.triangle_count() {
            return Err(RenderError::IndexCount {
                indices: n,
                triangles: scene.triangle_count(),
            });
        }
        Ok(())
    }
}
