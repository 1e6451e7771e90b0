//! The GLB container: the JSON chunk and the `BIN` chunk.

use crate::AssetError;

pub(super) const GLB_JSON: u32 = 0x4E4F_534A;
pub(super) const GLB_BIN: u32 = 0x004E_4942;

pub(super) fn le_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let word = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([word[0], word[1], word[2], word[3]]))
}

/// The JSON chunk and the first `BIN` chunk of a GLB.
pub(super) fn split_glb<'a>(
    bytes: &'a [u8],
    warnings: &mut Vec<String>,
) -> Result<(&'a [u8], Option<&'a [u8]>), AssetError> {
    let glb = |message: String| AssetError::Glb { message };
    let (Some(version), Some(length)) = (le_u32(bytes, 4), le_u32(bytes, 8)) else {
        return Err(glb(format!(
            "{} bytes, shorter than the 12-byte header",
            bytes.len()
        )));
    };
    if version != 2 {
        return Err(glb(format!("version {version}, expected 2")));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(glb(format!(
            "header says {length} bytes, the data has {} (truncated?)",
            bytes.len()
        )));
    }
    if length < bytes.len() {
        warnings.push(format!(
            "GLB: {} bytes after the length of {length} in the header ignored",
            bytes.len() - length
        ));
    }
    let bytes = &bytes[..length.max(12)];
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    let mut chunk = 0usize;
    while at < bytes.len() {
        let (Some(chunk_length), Some(chunk_type)) = (le_u32(bytes, at), le_u32(bytes, at + 4))
        else {
            return Err(glb(format!(
                "{} bytes at offset {at}, too few for a chunk header",
                bytes.len() - at
            )));
        };
        let start = at + 8;
        let end = start
            .checked_add(chunk_length as usize)
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| {
                glb(format!(
                    "chunk {chunk} at offset {at}: length {chunk_length} runs past the end ({} bytes)",
                    bytes.len()
                ))
            })?;
        if chunk_length % 4 != 0 {
            warnings.push(format!(
                "GLB: chunk {chunk} length {chunk_length} is not a multiple of 4"
            ));
        }
        let data = &bytes[start..end];
        match (chunk, chunk_type) {
            (0, GLB_JSON) => json = Some(data),
            (0, other) => {
                return Err(glb(format!(
                    "the first chunk has type 0x{other:08x}, expected JSON (0x{GLB_JSON:08x})"
                )))
            }
            (_, GLB_JSON) => return Err(glb(format!("chunk {chunk} is a second JSON chunk"))),
            (_, GLB_BIN) if bin.is_none() => bin = Some(data),
            (_, GLB_BIN) => {
                warnings.push(format!("GLB: chunk {chunk}, a second BIN chunk, ignored"));
            }
            // Unknown chunk types are ignored, as the specification says.
            _ => {}
        }
        at = end;
        chunk += 1;
    }
    let json = json.ok_or_else(|| glb("no JSON chunk".to_string()))?;
    // Some writers pad the JSON chunk with NUL instead of spaces.
    let trimmed = json.len() - json.iter().rev().take_while(|&&b| b == 0).count();
    Ok((&json[..trimmed], bin))
}
