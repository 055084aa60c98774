//! A small glTF 2.0 scene written by the tests (a textured floor, a block under a node
//! transform, a spot light and a camera): as `.gltf` with an external buffer and image, as
//! `.glb` with everything embedded, or as its JSON and binary buffer for a fuzzing pass to mutate.

use std::path::{Path, PathBuf};

use glam::{Mat4, Quat};
use serde_json::json;

pub const CANDELA: f32 = 40.0;
pub const INNER: f32 = 0.7;
pub const OUTER: f32 = 1.1;
pub const LIGHT_COLOR: [f32; 3] = [1.0, 0.9, 0.8];
pub const YFOV: f32 = 0.75;

/// Floor: a unit quad in its node's frame (the node scales it by 2 in x and z), texture
/// coordinates 0..2 (the 4x4 texture repeats twice).
pub const FLOOR: [[f32; 3]; 4] = [
    [-0.5, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.5, 0.0, -0.5],
    [-0.5, 0.0, -0.5],
];
pub const FLOOR_UV: [[f32; 2]; 4] = [[0.0, 2.0], [2.0, 2.0], [2.0, 0.0], [0.0, 0.0]];
pub const FLOOR_INDICES: [u16; 6] = [0, 1, 2, 0, 2, 3];
pub const FLOOR_SCALE: [f32; 3] = [2.0, 1.0, 2.0];

/// Block half-sizes (the node turns it 90° about y and moves it).
pub const BLOCK_HALF: [f32; 3] = [0.3, 0.25, 0.125];

/// The block node: 90° about y (x → -z, z → x), then moved by (0.25, 0.25, -0.25).
pub fn block_matrix() -> Mat4 {
    Mat4::from_cols_array(&[
        0.0, 0.0, -1.0, 0.0, //
        0.0, 1.0, 0.0, 0.0, //
        1.0, 0.0, 0.0, 0.0, //
        0.25, 0.25, -0.25, 1.0,
    ])
}

/// The light node: -z turned to -y (90° about x), at (0, 1.75, 0).
pub fn light_matrix() -> Mat4 {
    Mat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, -1.0, 0.0, //
        0.0, 1.0, 0.0, 0.0, //
        0.0, 1.75, 0.0, 1.0,
    ])
}

pub const CAMERA_AT: [f32; 3] = [0.0, 1.6, 2.2];
/// The camera node turns the view down by this angle (radians) about x, onto the floor.
pub const CAMERA_PITCH: f32 = 0.63;

pub fn camera_rotation() -> Quat {
    Quat::from_rotation_x(-CAMERA_PITCH)
}

/// The block's corners and outward triangles (counter-clockwise seen from outside).
pub fn block() -> (Vec<[f32; 3]>, Vec<u16>) {
    let [x, y, z] = BLOCK_HALF;
    let corners: Vec<[f32; 3]> = (0..8)
        .map(|i| {
            [
                if i & 1 == 0 { -x } else { x },
                if i & 2 == 0 { -y } else { y },
                if i & 4 == 0 { -z } else { z },
            ]
        })
        .collect();
    let quads = [
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ];
    let indices = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [a, b, c, a, c, d])
        .collect();
    (corners, indices)
}

/// A 4x4 texture of distinct colours, as PNG bytes.
pub fn texture_png() -> Vec<u8> {
    let image = image::RgbaImage::from_fn(4, 4, |x, y| {
        let i = (y * 4 + x).wrapping_mul(0x9E37_79B9) >> 8;
        image::Rgba([i as u8, (i >> 8) as u8, (i >> 16) as u8, 255])
    });
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    bytes
}

/// The binary buffer and the glTF JSON describing it. With `embed_image` the PNG is a buffer
/// view; otherwise the JSON names `texture.png` beside the file.
pub fn gltf_document(embed_image: bool, buffer_uri: Option<&str>) -> (serde_json::Value, Vec<u8>) {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut push = |bytes: &[u8], target: Option<u32>| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        let mut view = json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()});
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        views.push(view);
        views.len() - 1
    };
    let floats =
        |v: &[[f32; 3]]| -> Vec<u8> { v.iter().flatten().flat_map(|f| f.to_le_bytes()).collect() };
    let (block_corners, block_indices) = block();
    let shorts = |v: &[u16]| -> Vec<u8> { v.iter().flat_map(|s| s.to_le_bytes()).collect() };
    let floor_position = push(&floats(&FLOOR), Some(34962));
    let floor_normal = push(&floats(&[[0.0, 1.0, 0.0]; 4]), Some(34962));
    let uv: Vec<u8> = FLOOR_UV
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let floor_uv = push(&uv, Some(34962));
    let floor_index = push(&shorts(&FLOOR_INDICES), Some(34963));
    let block_position = push(&floats(&block_corners), Some(34962));
    let block_index = push(&shorts(&block_indices), Some(34963));
    let image = if embed_image {
        let view = push(&texture_png(), None);
        json!({"bufferView": view, "mimeType": "image/png"})
    } else {
        json!({"uri": "texture.png"})
    };
    let bounds = |v: &[[f32; 3]]| {
        let min = (0..3)
            .map(|k| v.iter().map(|p| p[k]).fold(f32::MAX, f32::min))
            .collect::<Vec<_>>();
        let max = (0..3)
            .map(|k| v.iter().map(|p| p[k]).fold(f32::MIN, f32::max))
            .collect::<Vec<_>>();
        (min, max)
    };
    let (floor_min, floor_max) = bounds(&FLOOR);
    let (block_min, block_max) = bounds(&block_corners);
    let mut buffer = json!({"byteLength": bin.len()});
    if let Some(uri) = buffer_uri {
        buffer["uri"] = json!(uri);
    }
    let document = json!({
        "asset": {"version": "2.0", "generator": "vkgi tests/gltf.rs"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{
            "type": "spot", "color": LIGHT_COLOR, "intensity": CANDELA,
            "spot": {"innerConeAngle": INNER, "outerConeAngle": OUTER}
        }]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0, "scale": FLOOR_SCALE},
            {"mesh": 1, "matrix": block_matrix().to_cols_array()},
            {"matrix": light_matrix().to_cols_array(),
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"camera": 0, "translation": CAMERA_AT,
             "rotation": camera_rotation().to_array()}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": YFOV, "znear": 0.01}}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                             "indices": 3, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 4}, "indices": 5, "material": 1}]}
        ],
        "materials": [
            {"name": "floor", "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 0.9, 0.8, 1.0], "baseColorTexture": {"index": 0},
                "metallicFactor": 0.0}},
            {"name": "block", "pbrMetallicRoughness": {
                "baseColorFactor": [0.6, 0.3, 0.2, 1.0], "metallicFactor": 0.0}}
        ],
        "textures": [{"source": 0}],
        "images": [image],
        "accessors": [
            {"bufferView": floor_position, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": floor_min, "max": floor_max},
            {"bufferView": floor_normal, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": floor_uv, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": floor_index, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": block_position, "componentType": 5126, "count": 8, "type": "VEC3",
             "min": block_min, "max": block_max},
            {"bufferView": block_index, "componentType": 5123, "count": block_indices.len(),
             "type": "SCALAR"}
        ],
        "bufferViews": views,
        "buffers": [buffer]
    });
    (document, bin)
}

/// `.gltf` + `scene.bin` + `texture.png`.
pub fn write_gltf(dir: &Path) -> PathBuf {
    let (document, bin) = gltf_document(false, Some("scene.bin"));
    std::fs::write(dir.join("scene.bin"), bin).unwrap();
    std::fs::write(dir.join("texture.png"), texture_png()).unwrap();
    let path = dir.join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&document).unwrap()).unwrap();
    path
}

/// A `.glb`: JSON and binary chunks, the image inside the binary one.
pub fn write_glb(dir: &Path) -> PathBuf {
    let (document, bin) = gltf_document(true, None);
    let path = dir.join("scene.glb");
    std::fs::write(&path, glb_bytes(&document, bin)).unwrap();
    path
}

/// The `.glb` container of a JSON document and its binary buffer (both chunks padded to 4
/// bytes, as the format requires).
pub fn glb_bytes(document: &serde_json::Value, mut bin: Vec<u8>) -> Vec<u8> {
    let mut text = serde_json::to_vec(document).unwrap();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(text.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&text);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    glb
}
