//! A stereo pair laid out for eyes without shutter glasses: side by side (cross-free parallel
//! viewing), top-bottom, or a red-cyan anaglyph (red from the left eye, green and blue from the
//! right).

/// How a node shows its two eyes.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum StereoLayout {
    SideBySide,
    TopBottom,
    Anaglyph,
}

/// Lay out two RGBA8 images of `width` x `height` (left eye, right eye); returns the image and
/// its size.
pub fn compose(
    layout: StereoLayout,
    left: &[u8],
    right: &[u8],
    (width, height): (u32, u32),
) -> (Vec<u8>, (u32, u32)) {
    let row = 4 * width as usize;
    match layout {
        StereoLayout::SideBySide => {
            let mut out = Vec::with_capacity(2 * left.len());
            for (l, r) in left.chunks_exact(row).zip(right.chunks_exact(row)) {
                out.extend_from_slice(l);
                out.extend_from_slice(r);
            }
            (out, (2 * width, height))
        }
        StereoLayout::TopBottom => ([left, right].concat(), (width, 2 * height)),
        StereoLayout::Anaglyph => {
            let out = left
                .chunks_exact(4)
                .zip(right.chunks_exact(4))
                .flat_map(|(l, r)| [l[0], r[1], r[2], 255])
                .collect();
            (out, (width, height))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_place_each_eye_where_it_belongs() {
        // 2x1 images: the left eye's pixels are (1,2,3) and (4,5,6), the right's (7,8,9), (10,11,12).
        let left = [1, 2, 3, 255, 4, 5, 6, 255];
        let right = [7, 8, 9, 255, 10, 11, 12, 255];
        let (sbs, size) = compose(StereoLayout::SideBySide, &left, &right, (2, 1));
        assert_eq!(size, (4, 1));
        assert_eq!(sbs, [left, right].concat());
        let (tb, size) = compose(StereoLayout::TopBottom, &left, &right, (2, 1));
        assert_eq!((tb.len(), size), (16, (2, 2)));
        let (ana, size) = compose(StereoLayout::Anaglyph, &left, &right, (2, 1));
        assert_eq!(size, (2, 1));
        assert_eq!(ana, [1, 8, 9, 255, 4, 11, 12, 255]);
        // Two rows side by side interleave row by row.
        let (two_rows, _) = compose(
            StereoLayout::SideBySide,
            &[1, 1, 1, 1, 2, 2, 2, 2],
            &[3, 3, 3, 3, 4, 4, 4, 4],
            (1, 2),
        );
        assert_eq!(two_rows, [1, 1, 1, 1, 3, 3, 3, 3, 2, 2, 2, 2, 4, 4, 4, 4]);
    }
}
