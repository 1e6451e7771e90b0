//! Images: each `images[i]` the primitives use, from a URI or a buffer
//! view, decoded once.

use super::asset::GltfImageInfo;
use super::reader::Reader;
use super::uri::uri_label;
use crate::{decode_image_alpha, AlphaSource, AssetError, Limits, MissingAlpha};
use std::borrow::Cow;

impl Reader<'_, '_> {
    /// Decodes image `index` (once); its position in `asset.images`.
    pub(super) fn image(&mut self, index: usize, what: &str) -> Result<usize, AssetError> {
        if let Some(&position) = self.images.get(&index) {
            return Ok(position);
        }
        let image = self.root.element("images", index, what)?;
        let uri = image.opt_str("uri")?;
        let view = image.opt_usize("bufferView")?;
        let limits = Limits {
            max_pixels: self.limits.max_pixels,
            max_bytes: self.budget.left,
            ..self.limits
        };
        let (bytes, label): (Cow<'_, [u8]>, String) = match (uri, view) {
            (Some(uri), None) => {
                let label = format!("{} (uri {:?})", image.path, uri_label(uri));
                let bytes = self.load_uri(uri).map_err(|e| e.within(&label))?;
                (Cow::Owned(bytes), label)
            }
            (None, Some(view)) => {
                let label = format!("{} (bufferViews[{view}])", image.path);
                let (bytes, _) = self.view_bytes(view, &image.field("bufferView"))?;
                (Cow::Borrowed(bytes), label)
            }
            (Some(_), Some(_)) => return Err(image.error("uri", "given together with bufferView")),
            (None, None) => return Err(image.error("uri", "missing, and no bufferView either")),
        };
        // glTF: an image without an alpha channel has alpha 1.
        let decoded =
            decode_image_alpha(&bytes, &limits, MissingAlpha::One).map_err(|e| e.within(&label));
        drop(bytes);
        let (decoded, alpha) = decoded?;
        if alpha == AlphaSource::One {
            self.warn(format!(
                "{label} has no alpha channel: its alpha is 1 (glTF), so every texel is opaque"
            ));
        }
        let texel_bytes = decoded.texels.byte_len();
        self.budget.take(|| label.clone(), texel_bytes)?;
        let info = GltfImageInfo {
            index,
            uri: uri.map(|uri| {
                if uri.starts_with("data:") {
                    uri_label(uri)
                } else {
                    uri.to_string()
                }
            }),
            buffer_view: view,
            mime_type: image.opt_str("mimeType")?.map(str::to_string),
            name: image.opt_str("name")?.map(str::to_string),
            alpha,
        };
        let position = self.asset.images.len();
        self.asset.images.push(decoded);
        self.asset.image_info.push(info);
        self.images.insert(index, position);
        Ok(position)
    }
}
