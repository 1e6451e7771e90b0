//! `POSITION`: the vertex positions of a primitive, gathered per triangle,
//! for renderers (`micromap-index render` traces rays against them).

use super::accessor::component_name;
use super::reader::{bytes_of, Reader};
use crate::AssetError;

impl Reader<'_, '_> {
    /// The positions of each triangle of a primitive, through its indices
    /// (`count` triangles, checked against the UVs already): `POSITION`
    /// must be `VEC3` of `FLOAT`, as glTF requires without
    /// `KHR_mesh_quantization`; every value finite.
    pub(super) fn triangle_positions(
        &mut self,
        path: &str,
        accessor_index: usize,
        indices: Option<&[u32]>,
        count: usize,
    ) -> Result<Vec<[[f32; 3]; 3]>, AssetError> {
        let what = format!("{path}.attributes.POSITION");
        let (accessor, layout) = self.layout(accessor_index, &what, "VEC3", 3)?;
        if layout.component_type != 5126 || layout.normalized {
            return Err(accessor.error(
                "componentType",
                format!(
                    "{} ({}), expected FLOAT for positions (quantized positions are not supported)",
                    layout.component_type,
                    component_name(layout.component_type)
                ),
            ));
        }
        let vertices = self.elements(&accessor, &layout, |c| {
            let f = |i: usize| f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]);
            [f(0), f(4), f(8)]
        })?;
        if let Some(i) = vertices
            .iter()
            .position(|p| p.iter().any(|x| !x.is_finite()))
        {
            return Err(AssetError::gltf(
                &layout.path,
                format!("element {i} is {:?}, not finite", vertices[i]),
            ));
        }
        self.budget.take(
            || format!("{path} ({count} triangles' positions)"),
            bytes_of(count as u64, 36),
        )?;
        let mut triangles = Vec::with_capacity(count);
        for t in 0..count {
            let mut triangle = [[0f32; 3]; 3];
            for (k, corner) in triangle.iter_mut().enumerate() {
                let position = 3 * t + k;
                let vertex = indices.map_or(position, |i| i[position] as usize);
                *corner = *vertices.get(vertex).ok_or_else(|| {
                    AssetError::gltf(
                        &what,
                        format!(
                            "vertex {vertex} (corner {position}) is past the {} positions",
                            vertices.len()
                        ),
                    )
                })?;
            }
            triangles.push(triangle);
        }
        Ok(triangles)
    }
}
