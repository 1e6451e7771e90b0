//! Buffers, buffer views and accessors: UVs (`KHR_mesh_quantization`
//! included), indices, sparse substitution, and the triangles they make.

use super::json::Obj;
use super::reader::{bytes_of, Reader};
use super::uri::uri_label;
use crate::AssetError;
use std::borrow::Cow;
use std::rc::Rc;

/// An accessor's layout and where its elements are.
pub(super) struct Layout {
    pub(super) path: String,
    pub(super) count: usize,
    pub(super) component_type: u64,
    pub(super) normalized: bool,
    pub(super) element_size: usize,
}

pub(super) fn component_size(component_type: u64) -> Option<usize> {
    match component_type {
        5120 | 5121 => Some(1),
        5122 | 5123 => Some(2),
        5125 | 5126 => Some(4),
        _ => None,
    }
}

pub(super) fn component_name(component_type: u64) -> &'static str {
    match component_type {
        5120 => "BYTE",
        5121 => "UNSIGNED_BYTE",
        5122 => "SHORT",
        5123 => "UNSIGNED_SHORT",
        5125 => "UNSIGNED_INT",
        5126 => "FLOAT",
        _ => "unknown",
    }
}

/// A little-endian unsigned integer of 1, 2 or 4 bytes.
pub(super) fn read_unsigned(bytes: &[u8]) -> u32 {
    match *bytes {
        [a] => u32::from(a),
        [a, b] => u32::from(u16::from_le_bytes([a, b])),
        [a, b, c, d] => u32::from_le_bytes([a, b, c, d]),
        _ => 0,
    }
}

impl<'a> Reader<'a, '_> {
    /// Loads buffer `index` (once) and checks its length.
    pub(super) fn load_buffer(&mut self, index: usize, what: &str) -> Result<(), AssetError> {
        if self.buffers.contains_key(&index) {
            return Ok(());
        }
        let buffer = self.root.element("buffers", index, what)?;
        let length = buffer.usize("byteLength")?;
        let data: Cow<'a, [u8]> = match buffer.opt_str("uri")? {
            Some(uri) => {
                self.budget.take(|| buffer.path.clone(), length as u64)?;
                Cow::Owned(
                    self.load_uri(uri).map_err(|e| {
                        e.within(format!("{} (uri {:?})", buffer.path, uri_label(uri)))
                    })?,
                )
            }
            None if index == 0 => Cow::Borrowed(self.bin.ok_or_else(|| {
                buffer.error(
                    "uri",
                    "missing, and there is no GLB BIN chunk to stand for buffer 0",
                )
            })?),
            None => {
                return Err(buffer.error("uri", "missing (only buffer 0 can be the GLB BIN chunk)"))
            }
        };
        if data.len() < length {
            return Err(buffer.error(
                "byteLength",
                format!("{length}, but the data has {} bytes", data.len()),
            ));
        }
        let data = match data {
            Cow::Borrowed(data) => Cow::Borrowed(&data[..length]),
            Cow::Owned(mut data) => {
                data.truncate(length);
                Cow::Owned(data)
            }
        };
        self.buffers.insert(index, data);
        Ok(())
    }

    /// Buffer view `index`: (buffer, start, length, byteStride), with its
    /// buffer loaded and the range checked.
    pub(super) fn view(
        &mut self,
        index: usize,
        what: &str,
    ) -> Result<(usize, usize, usize, Option<usize>), AssetError> {
        let view = self.root.element("bufferViews", index, what)?;
        let buffer = view.usize("buffer")?;
        let offset = view.opt_usize("byteOffset")?.unwrap_or(0);
        let length = view.usize("byteLength")?;
        let stride = view.opt_usize("byteStride")?;
        if let Some(stride) = stride {
            if !(4..=252).contains(&stride) || stride % 4 != 0 {
                return Err(view.error(
                    "byteStride",
                    format!("{stride}, expected a multiple of 4 in 4..=252"),
                ));
            }
        }
        self.load_buffer(buffer, &view.field("buffer"))?;
        let available = self.buffers.get(&buffer).map_or(0, |data| data.len());
        if !matches!(offset.checked_add(length), Some(end) if end <= available) {
            return Err(view.error(
                "byteLength",
                format!(
                    "bytes {offset}..{offset}+{length} run past the end of buffers[{buffer}] ({available} bytes)"
                ),
            ));
        }
        Ok((buffer, offset, length, stride))
    }

    /// The bytes of buffer view `index` and its `byteStride`.
    pub(super) fn view_bytes(
        &mut self,
        index: usize,
        what: &str,
    ) -> Result<(&[u8], Option<usize>), AssetError> {
        let (buffer, start, length, stride) = self.view(index, what)?;
        let bytes = self
            .buffers
            .get(&buffer)
            .and_then(|data| data.get(start..start + length))
            .ok_or_else(|| AssetError::gltf(what, "buffer view out of range"))?;
        Ok((bytes, stride))
    }

    /// The layout of accessor `index`, whose type must be `ty`.
    pub(super) fn layout(
        &self,
        index: usize,
        what: &str,
        ty: &str,
        components: usize,
    ) -> Result<(Obj<'a>, Layout), AssetError> {
        let accessor = self.root.element("accessors", index, what)?;
        let component_type = accessor
            .opt_u64("componentType")?
            .ok_or_else(|| accessor.error("componentType", "missing"))?;
        let size = component_size(component_type).ok_or_else(|| {
            accessor.error(
                "componentType",
                format!("{component_type} is not a glTF component type"),
            )
        })?;
        let actual = accessor.str("type")?;
        if actual != ty {
            return Err(accessor.error("type", format!("{actual:?}, expected {ty:?} for {what}")));
        }
        let count = accessor.usize("count")?;
        let normalized = accessor.opt_bool("normalized")?.unwrap_or(false);
        let layout = Layout {
            path: accessor.path.clone(),
            count,
            component_type,
            normalized,
            element_size: size * components,
        };
        Ok((accessor, layout))
    }

    /// The elements of an accessor, each decoded from its bytes by
    /// `decode`: from its buffer view (zeros without one), then the sparse
    /// substitutions. `T` is budgeted at `size_of::<T>()` bytes.
    pub(super) fn elements<T: Copy + Default>(
        &mut self,
        accessor: &Obj<'a>,
        layout: &Layout,
        decode: impl Fn(&[u8]) -> T,
    ) -> Result<Vec<T>, AssetError> {
        let count = layout.count;
        self.budget.take(
            || format!("{} ({count} elements)", layout.path),
            bytes_of(count as u64, std::mem::size_of::<T>() as u64),
        )?;
        let mut values = if let Some(view_index) = accessor.opt_usize("bufferView")? {
            self.dense(accessor, layout, view_index, &decode)?
        } else {
            if accessor.opt_usize("byteOffset")?.unwrap_or(0) != 0 {
                return Err(accessor.error("byteOffset", "given without a bufferView"));
            }
            vec![T::default(); count]
        };
        if let Some(sparse) = accessor.opt_obj("sparse")? {
            self.sparse(&sparse, layout, &mut values, &decode)?;
        }
        Ok(values)
    }

    /// The elements of an accessor in buffer view `view_index`.
    pub(super) fn dense<T>(
        &mut self,
        accessor: &Obj<'a>,
        layout: &Layout,
        view_index: usize,
        decode: &impl Fn(&[u8]) -> T,
    ) -> Result<Vec<T>, AssetError> {
        let count = layout.count;
        let size = layout.element_size;
        let mut values = Vec::new();
        let offset = accessor.opt_usize("byteOffset")?.unwrap_or(0);
        let (bytes, stride) = self.view_bytes(view_index, &accessor.field("bufferView"))?;
        let stride = stride.unwrap_or(size);
        if stride < size {
            return Err(accessor.error(
                "bufferView",
                format!(
                    "bufferViews[{view_index}].byteStride {stride} is less than the element size {size}"
                ),
            ));
        }
        // The last element ends at offset + stride * (count - 1) + size.
        let end = count.checked_sub(1).map_or(Some(0), |last| {
            stride
                .checked_mul(last)
                .and_then(|n| n.checked_add(size))
                .and_then(|n| n.checked_add(offset))
        });
        match end {
            Some(end) if end <= bytes.len() || count == 0 => {}
            _ => {
                return Err(accessor.error(
                    "count",
                    format!(
                        "{count} elements of {size} bytes, stride {stride}, from byte {offset} run past the end of bufferViews[{view_index}] ({} bytes)",
                        bytes.len()
                    ),
                ))
            }
        }
        values.reserve_exact(count);
        for i in 0..count {
            let start = offset + i * stride;
            values.push(decode(&bytes[start..start + size]));
        }
        Ok(values)
    }

    /// Applies `accessor.sparse` to `values`.
    pub(super) fn sparse<T>(
        &mut self,
        sparse: &Obj<'a>,
        layout: &Layout,
        values: &mut [T],
        decode: &impl Fn(&[u8]) -> T,
    ) -> Result<(), AssetError> {
        let count = sparse.usize("count")?;
        if count == 0 || count > values.len() {
            return Err(sparse.error(
                "count",
                format!(
                    "{count}, expected 1..={} (the accessor's count)",
                    values.len()
                ),
            ));
        }
        let indices = sparse.obj("indices")?;
        let index_type = indices
            .opt_u64("componentType")?
            .ok_or_else(|| indices.error("componentType", "missing"))?;
        let index_size = match index_type {
            5121 => 1,
            5123 => 2,
            5125 => 4,
            other => {
                return Err(indices.error(
                    "componentType",
                    format!("{other}, expected 5121, 5123 or 5125 (unsigned)"),
                ))
            }
        };
        let index_offset = indices.opt_usize("byteOffset")?.unwrap_or(0);
        let index_view = indices.usize("bufferView")?;
        let (index_bytes, _) = self.view_bytes(index_view, &indices.field("bufferView"))?;
        let index_bytes = count
            .checked_mul(index_size)
            .and_then(|n| n.checked_add(index_offset))
            .and_then(|end| index_bytes.get(index_offset..end))
            .ok_or_else(|| {
                indices.error(
                    "bufferView",
                    format!("{count} indices of {index_size} bytes from byte {index_offset} run past the end of bufferViews[{index_view}]"),
                )
            })?
            .to_vec();
        let value_info = sparse.obj("values")?;
        let value_offset = value_info.opt_usize("byteOffset")?.unwrap_or(0);
        let value_view = value_info.usize("bufferView")?;
        let size = layout.element_size;
        let (value_bytes, _) = self.view_bytes(value_view, &value_info.field("bufferView"))?;
        let value_bytes = count
            .checked_mul(size)
            .and_then(|n| n.checked_add(value_offset))
            .and_then(|end| value_bytes.get(value_offset..end))
            .ok_or_else(|| {
                value_info.error(
                    "bufferView",
                    format!("{count} values of {size} bytes from byte {value_offset} run past the end of bufferViews[{value_view}]"),
                )
            })?;
        for (k, (index, value)) in index_bytes
            .chunks_exact(index_size)
            .zip(value_bytes.chunks_exact(size))
            .enumerate()
        {
            let index = read_unsigned(index) as usize;
            let slot = values.get_mut(index).ok_or_else(|| {
                indices.error(
                    "bufferView",
                    format!(
                        "sparse index {k} is {index}, past the accessor's count {}",
                        layout.count
                    ),
                )
            })?;
            *slot = decode(value);
        }
        Ok(())
    }

    /// The UVs of accessor `index` (decoded once).
    pub(super) fn uvs(
        &mut self,
        index: usize,
        what: &str,
    ) -> Result<Rc<Vec<[f32; 2]>>, AssetError> {
        if let Some(uvs) = self.uvs.get(&index) {
            return Ok(Rc::clone(uvs));
        }
        let (accessor, layout) = self.layout(index, what, "VEC2", 2)?;
        let normalized = layout.normalized;
        let convert: fn(&[u8], bool) -> f32 = match layout.component_type {
            5126 if !normalized => |c, _| f32::from_le_bytes([c[0], c[1], c[2], c[3]]),
            5121 => |c, n| {
                let c = f32::from(c[0]);
                if n { c / 255.0 } else { c }
            },
            5123 => |c, n| {
                let c = f32::from(u16::from_le_bytes([c[0], c[1]]));
                if n { c / 65535.0 } else { c }
            },
            5120 => |c, n| {
                let c = f32::from(c[0] as i8);
                if n { (c / 127.0).max(-1.0) } else { c }
            },
            5122 => |c, n| {
                let c = f32::from(i16::from_le_bytes([c[0], c[1]]));
                if n { (c / 32767.0).max(-1.0) } else { c }
            },
            other => {
                return Err(accessor.error(
                    "componentType",
                    format!(
                        "{other} ({}{}) is not a texture coordinate type (FLOAT, or UNSIGNED_BYTE, UNSIGNED_SHORT, BYTE, SHORT)",
                        if normalized { "normalized " } else { "" },
                        component_name(other)
                    ),
                ))
            }
        };
        let half = layout.element_size / 2;
        let uvs = self.elements(&accessor, &layout, |bytes| {
            [
                convert(&bytes[..half], normalized),
                convert(&bytes[half..], normalized),
            ]
        })?;
        let uvs = Rc::new(uvs);
        self.uvs.insert(index, Rc::clone(&uvs));
        Ok(uvs)
    }

    /// The alpha of each vertex of `COLOR_0` accessor `index`: `None` for
    /// `VEC3` (alpha 1); for `VEC4`, `FLOAT` in `[0, 1]`, or normalized
    /// `UNSIGNED_BYTE` (`c / 255`) or `UNSIGNED_SHORT` (`c / 65535`), each
    /// one binary32 division, as glTF allows.
    pub(super) fn vertex_alphas(
        &mut self,
        index: usize,
        what: &str,
    ) -> Result<Option<Vec<f32>>, AssetError> {
        let accessor = self.root.element("accessors", index, what)?;
        match accessor.str("type")? {
            "VEC3" => return Ok(None),
            "VEC4" => {}
            other => {
                return Err(accessor.error(
                    "type",
                    format!("{other:?}, expected \"VEC3\" or \"VEC4\" for {what}"),
                ))
            }
        }
        let (accessor, layout) = self.layout(index, what, "VEC4", 4)?;
        let convert: fn(&[u8]) -> f32 = match (layout.component_type, layout.normalized) {
            (5126, false) => |c| f32::from_le_bytes([c[12], c[13], c[14], c[15]]),
            (5121, true) => |c| f32::from(c[3]) / 255.0,
            (5123, true) => |c| f32::from(u16::from_le_bytes([c[6], c[7]])) / 65535.0,
            (other, normalized) => {
                return Err(accessor.error(
                    "componentType",
                    format!(
                        "{other} ({}{}) is not a vertex colour type (FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT)",
                        if normalized { "normalized " } else { "" },
                        component_name(other)
                    ),
                ))
            }
        };
        let alphas = self.elements(&accessor, &layout, convert)?;
        if let Some((i, bad)) = alphas
            .iter()
            .enumerate()
            .find(|(_, a)| !(0.0..=1.0).contains(*a))
        {
            return Err(AssetError::gltf(
                &layout.path,
                format!("element {i} has alpha {bad}, outside [0, 1]"),
            ));
        }
        Ok(Some(alphas))
    }

    /// The vertex indices of accessor `index`.
    pub(super) fn indices(&mut self, index: usize, what: &str) -> Result<Vec<u32>, AssetError> {
        let (accessor, layout) = self.layout(index, what, "SCALAR", 1)?;
        if !matches!(layout.component_type, 5121 | 5123 | 5125) || layout.normalized {
            return Err(accessor.error(
                "componentType",
                format!(
                    "{} ({}{}), expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT for indices",
                    layout.component_type,
                    if layout.normalized { "normalized " } else { "" },
                    component_name(layout.component_type)
                ),
            ));
        }
        self.elements(&accessor, &layout, read_unsigned)
    }

    /// The vertex alphas of each triangle of a primitive, through its
    /// indices (checked by [`triangles`](Self::triangles) for the UVs; here
    /// against the colours).
    pub(super) fn triangle_alphas(
        &mut self,
        path: &str,
        alphas: &[f32],
        indices: Option<&[u32]>,
        count: usize,
    ) -> Result<Vec<[f32; 3]>, AssetError> {
        self.budget.take(
            || format!("{path} ({count} triangles' vertex alphas)"),
            bytes_of(count as u64, 12),
        )?;
        gather_corners(alphas, indices, count, |position, vertex| {
            AssetError::gltf(
                format!("{path}.attributes.COLOR_0"),
                format!(
                    "vertex {vertex} (corner {position}) is past the {} colours",
                    alphas.len()
                ),
            )
        })
    }

    /// The triangles of a primitive: its UVs through its indices.
    pub(super) fn triangles(
        &mut self,
        path: &str,
        uvs: &[[f32; 2]],
        indices: Option<&[u32]>,
    ) -> Result<Vec<[[f32; 2]; 3]>, AssetError> {
        let corners = indices.map_or(uvs.len(), <[u32]>::len);
        if corners % 3 != 0 {
            self.warn(format!(
                "{path}: {corners} {}, not a multiple of 3: the last {} ignored",
                if indices.is_some() {
                    "indices"
                } else {
                    "vertices"
                },
                corners % 3
            ));
        }
        let count = corners / 3;
        self.budget.take(
            || format!("{path} ({count} triangles)"),
            bytes_of(count as u64, 24),
        )?;
        gather_corners(uvs, indices, count, |position, vertex| {
            AssetError::gltf(
                format!("{path}.indices"),
                format!(
                    "index {position} is {vertex}, past the {} texture coordinates",
                    uvs.len()
                ),
            )
        })
    }
}

/// The per-corner values of `count` triangles: corner `position` (`3 t +
/// k` for corner `k` of triangle `t`) is `values[indices[position]]`, or
/// `values[position]` without indices. The one gather of the UVs and the
/// vertex alphas; a vertex past `values` is `past(position, vertex)`.
/// The caller has taken the result's bytes from the asset's budget, and
/// `indices` (if any) holds at least `3 count` entries.
fn gather_corners<T: Copy>(
    values: &[T],
    indices: Option<&[u32]>,
    count: usize,
    past: impl Fn(usize, usize) -> AssetError,
) -> Result<Vec<[T; 3]>, AssetError> {
    let mut triangles = Vec::with_capacity(count);
    for t in 0..count {
        let corner = |k: usize| {
            let position = 3 * t + k;
            let vertex = match indices {
                Some(indices) => indices[position] as usize,
                None => position,
            };
            values
                .get(vertex)
                .copied()
                .ok_or_else(|| past(position, vertex))
        };
        triangles.push([corner(0)?, corner(1)?, corner(2)?]);
    }
    Ok(triangles)
}
