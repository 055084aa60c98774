//! Albedo textures: 8-bit sRGB-encoded texels, decoded to linear and filtered bilinearly between
//! texel centres with repeat wrapping. shaders-glsl/common/texture.glsl is the same rule on the
//! GPU; both sample at the surface point's texture coordinates, without mipmaps.

use std::path::Path;

use glam::{Vec2, Vec3};

use crate::error::{InputError, catch_library_panic};

/// Longest side of a texture, texels.
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// Most texels of all of a scene's textures together (256 MiB of RGBA8).
pub const MAX_SCENE_TEXELS: u64 = 1 << 26;

/// An RGBA8 image (alpha unused), sRGB-encoded as image files store albedo.
#[derive(Clone, PartialEq)]
pub struct Texture {
    /// Where it came from (a file path or a glTF image name), for messages.
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row-major from the top row, each texel `r | g << 8 | b << 16 | a << 24`.
    pub texels: Vec<u32>,
}

impl std::fmt::Debug for Texture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Texture({} {}x{})", self.name, self.width, self.height)
    }
}

/// sRGB-encoded value in [0, 1] to linear (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear value in [0, 1] to sRGB-encoded.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

impl Texture {
    /// A texture of `width` x `height` RGBA8 texels, size-checked.
    pub fn new(name: &str, width: u32, height: u32, texels: Vec<u32>) -> Result<Self, InputError> {
        if width == 0 || height == 0 || width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(InputError::new(format!(
                "{name}: texture is {width}x{height}; each side must be 1..={MAX_TEXTURE_SIDE}"
            )));
        }
        if texels.len() as u64 != u64::from(width) * u64::from(height) {
            return Err(InputError::new(format!(
                "{name}: texture data holds {} texels, not {width}x{height}",
                texels.len()
            )));
        }
        Ok(Texture {
            name: name.to_string(),
            width,
            height,
            texels,
        })
    }

    /// A texture from interleaved RGBA8 bytes.
    pub fn from_rgba8(
        name: &str,
        width: u32,
        height: u32,
        bytes: &[u8],
    ) -> Result<Self, InputError> {
        let texels = bytes
            .chunks_exact(4)
            .map(|p| u32::from_le_bytes([p[0], p[1], p[2], p[3]]))
            .collect();
        Texture::new(name, width, height, texels)
    }

    /// Read an image file (PNG, JPEG, ... as the `image` crate decodes them).
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let name = path.display().to_string();
        if !path.is_file() {
            return Err(InputError::new(format!("{name}: no such file (a texture)")));
        }
        let reader = image::ImageReader::open(path)
            .and_then(|r| r.with_guessed_format())
            .map_err(|e| InputError::new(format!("{name}: cannot read the texture: {e}")))?;
        let (width, height) = reader
            .into_dimensions()
            .map_err(|e| InputError::new(format!("{name}: malformed texture: {e}")))?;
        if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(InputError::new(format!(
                "{name}: texture is {width}x{height}; each side must be 1..={MAX_TEXTURE_SIDE}"
            )));
        }
        let image = catch_library_panic("the image decoder", || {
            image::open(path)
                .map_err(|e| InputError::new(format!("{name}: malformed texture: {e}")))
        })?
        .to_rgba8();
        Texture::from_rgba8(&name, image.width(), image.height(), image.as_raw())
    }

    /// Linear RGB of texel (x, y), wrapped.
    fn texel(&self, x: i64, y: i64) -> Vec3 {
        let x = x.rem_euclid(i64::from(self.width)) as usize;
        let y = y.rem_euclid(i64::from(self.height)) as usize;
        let t = self.texels[y * self.width as usize + x];
        Vec3::new(
            srgb_to_linear((t & 0xff) as f32 / 255.0),
            srgb_to_linear(((t >> 8) & 0xff) as f32 / 255.0),
            srgb_to_linear(((t >> 16) & 0xff) as f32 / 255.0),
        )
    }

    /// Linear RGB at texture coordinates `uv` (u right, v down the rows as glTF and image files
    /// have it), bilinear between texel centres, repeating.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let wrapped = uv - uv.floor();
        let x = wrapped.x * self.width as f32 - 0.5;
        let y = wrapped.y * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = self.texel(x0, y0).lerp(self.texel(x0 + 1, y0), fx);
        let bottom = self.texel(x0, y0 + 1).lerp(self.texel(x0 + 1, y0 + 1), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Texture {
        // 2x2: black, white / white, black (sRGB 255 = linear 1).
        Texture::new("c", 2, 2, vec![0, 0xffffff, 0xffffff, 0]).unwrap()
    }

    #[test]
    fn texel_centres_return_the_texel_and_edges_wrap() {
        let t = checker();
        assert_eq!(t.sample(Vec2::new(0.25, 0.25)), Vec3::ZERO);
        assert_eq!(t.sample(Vec2::new(0.75, 0.25)), Vec3::ONE);
        assert_eq!(t.sample(Vec2::new(1.25, -0.75)), Vec3::ZERO);
        // Half-way between a black and a white centre, across the wrap.
        assert!((t.sample(Vec2::new(0.0, 0.25)) - Vec3::splat(0.5)).length() < 1e-6);
        assert!((t.sample(Vec2::new(0.5, 0.5)) - Vec3::splat(0.5)).length() < 1e-6);
        assert!(t.sample(Vec2::new(1e30, -1e30)).is_finite());
    }

    #[test]
    fn srgb_round_trips_and_matches_known_values() {
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        for i in 0..=255 {
            let c = i as f32 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-5);
        }
    }

    #[test]
    fn sizes_are_checked() {
        assert!(Texture::new("t", 0, 1, vec![]).is_err());
        assert!(Texture::new("t", 2, 2, vec![0; 3]).is_err());
        assert!(Texture::new("t", MAX_TEXTURE_SIDE + 1, 1, vec![0; 16385]).is_err());
    }
}
