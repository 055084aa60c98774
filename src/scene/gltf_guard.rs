//! Checks run before the `gltf` crate reads a file, for malformed input it panics on rather
//! than refusing (found by tests/fuzz_gltf.rs): gltf-json 1.4.1 validates a primitive's
//! POSITION accessor by indexing the accessor array without a bounds check
//! (`primitive_validate_hook` in its mesh.rs), and gltf 1.4.1's `Image::source` unwraps an
//! image's `mimeType` when it has a `bufferView`, and its `uri` when it has none (image.rs),
//! and slices an image's buffer view out of its buffer without checking that the view lies
//! inside the buffer (import.rs).

use std::io::Read;
use std::path::Path;

use gltf::json::mesh::Semantic;
use gltf::json::validation::Checked;

use crate::error::InputError;

/// Refuse a file the gltf crate would panic on (see above). Anything else this cannot parse is
/// left to the gltf crate to report.
pub fn check(path: &Path, name: &str) -> Result<(), InputError> {
    let Some(json) = document_json(path) else {
        return Ok(());
    };
    let Ok(root) = gltf::json::Root::from_slice(&json) else {
        return Ok(());
    };
    check_position_accessors(&root, name)?;
    check_image_sources(&root, name)?;
    check_buffer_views(&root, name)
}

fn check_buffer_views(root: &gltf::json::Root, name: &str) -> Result<(), InputError> {
    for (v, view) in root.buffer_views.iter().enumerate() {
        let Some(buffer) = root.buffers.get(view.buffer.value()) else {
            continue; // the gltf crate's validation reports a missing buffer
        };
        let offset = view.byte_offset.map_or(0, |o| o.0);
        let end = offset.checked_add(view.byte_length.0);
        if end.is_none_or(|end| end > buffer.byte_length.0) {
            return Err(InputError::new(format!(
                "{name}: invalid glTF: bufferViews[{v}]: bytes {offset}..+{} lie outside buffer {} ({} bytes)",
                view.byte_length.0,
                view.buffer.value(),
                buffer.byte_length.0
            )));
        }
    }
    Ok(())
}

fn check_image_sources(root: &gltf::json::Root, name: &str) -> Result<(), InputError> {
    for (i, image) in root.images.iter().enumerate() {
        let problem = match (&image.buffer_view, &image.uri, &image.mime_type) {
            (Some(_), _, None) => "an image in a buffer view must have a mimeType",
            (None, None, _) => "an image must have a uri or a bufferView",
            _ => continue,
        };
        return Err(InputError::new(format!(
            "{name}: invalid glTF: images[{i}]: {problem}"
        )));
    }
    Ok(())
}

fn check_position_accessors(root: &gltf::json::Root, name: &str) -> Result<(), InputError> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&Checked::Valid(Semantic::Positions));
            if let Some(index) = position
                && index.value() >= root.accessors.len()
            {
                return Err(InputError::new(format!(
                    "{name}: invalid glTF: meshes[{m}].primitives[{p}].attributes.POSITION: accessor {} does not exist ({} accessors)",
                    index.value(),
                    root.accessors.len()
                )));
            }
        }
    }
    Ok(())
}

/// The JSON document of a `.gltf` (the whole file) or a `.glb` (its first chunk, read without
/// reading the binary chunk); None when the file cannot be read as either.
fn document_json(path: &Path) -> Option<Vec<u8>> {
    let mut file = std::fs::File::open(path).ok()?;
    let mut header = [0u8; 20];
    let read = file.read(&mut header).ok()?;
    if read < 20 || &header[..4] != b"glTF" {
        return std::fs::read(path).ok();
    }
    if &header[16..20] != b"JSON" {
        return None;
    }
    let length = u32::from_le_bytes(header[12..16].try_into().ok()?) as u64;
    let file_length = file.metadata().ok()?.len();
    if length > file_length {
        return None;
    }
    let mut json = Vec::with_capacity(length as usize);
    file.take(length).read_to_end(&mut json).ok()?;
    Some(json)
}
