//! An RGB picture in memory, and its PNG file.

/// `width × height` sRGB pixels, row by row from the top left.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The pixels, `width · height` of them, row-major.
    pub pixels: Vec<[u8; 3]>,
}

impl Image {
    /// A picture of one colour.
    pub fn filled(width: u32, height: u32, colour: [u8; 3]) -> Image {
        Image {
            width,
            height,
            pixels: vec![colour; width as usize * height as usize],
        }
    }

    /// The picture `factor` times smaller in each direction, each pixel the
    /// mean of the `factor × factor` block it replaces (the anti-aliasing of
    /// a picture rendered larger).
    pub fn downsampled(&self, factor: u32) -> Image {
        let factor = factor.max(1);
        let (w, h) = (self.width / factor, self.height / factor);
        let mut pixels = Vec::with_capacity(w as usize * h as usize);
        let n = f64::from(factor * factor);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 3];
                for dy in 0..factor {
                    let row = ((y * factor + dy) * self.width) as usize;
                    for dx in 0..factor {
                        let p = self.pixels[row + (x * factor + dx) as usize];
                        for c in 0..3 {
                            sum[c] += u32::from(p[c]);
                        }
                    }
                }
                pixels.push(sum.map(|s| (f64::from(s) / n).round() as u8));
            }
        }
        Image {
            width: w,
            height: h,
            pixels,
        }
    }

    /// `other` placed to the right of this picture, `gap` pixels of
    /// `background` between them (the shorter one padded at the bottom).
    pub fn beside(&self, other: &Image, gap: u32, background: [u8; 3]) -> Image {
        let width = self.width + gap + other.width;
        let height = self.height.max(other.height);
        let mut out = Image::filled(width, height, background);
        for (image, left) in [(self, 0), (other, self.width + gap)] {
            for y in 0..image.height {
                let from = (y * image.width) as usize;
                let to = (y * width + left) as usize;
                out.pixels[to..to + image.width as usize]
                    .copy_from_slice(&image.pixels[from..from + image.width as usize]);
            }
        }
        out
    }

    /// Copies `other` into this picture with its top left corner at
    /// (`left`, `top`); what falls outside is cut off.
    pub fn place(&mut self, other: &Image, left: u32, top: u32) {
        let width = other.width.min(self.width.saturating_sub(left)) as usize;
        for y in 0..other.height.min(self.height.saturating_sub(top)) {
            let from = (y * other.width) as usize;
            let to = ((top + y) * self.width + left) as usize;
            self.pixels[to..to + width].copy_from_slice(&other.pixels[from..from + width]);
        }
    }

    /// The picture as a PNG file (8-bit RGB).
    pub fn png(&self) -> Result<Vec<u8>, png::EncodingError> {
        self.png_compressed(png::Compression::default())
    }

    /// The picture as a PNG file (8-bit RGB), compressed as `compression`
    /// says (`Fast` takes a fraction of the default's time for files a
    /// little larger).
    pub fn png_compressed(
        &self,
        compression: png::Compression,
    ) -> Result<Vec<u8>, png::EncodingError> {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, self.width, self.height);
        encoder.set_compression(compression);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(self.pixels.as_flattened())?;
        writer.finish()?;
        Ok(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_blocks() {
        let mut image = Image::filled(4, 2, [0, 0, 0]);
        image.pixels[0] = [200, 100, 40];
        let small = image.downsampled(2);
        assert_eq!((small.width, small.height), (2, 1));
        assert_eq!(small.pixels, vec![[50, 25, 10], [0, 0, 0]]);
    }

    #[test]
    fn side_by_side_keeps_both_and_the_gap() {
        let a = Image::filled(2, 2, [255, 0, 0]);
        let b = Image::filled(3, 1, [0, 0, 255]);
        let both = a.beside(&b, 1, [9, 9, 9]);
        assert_eq!((both.width, both.height), (6, 2));
        assert_eq!(both.pixels[0..6].to_vec(), {
            let mut row = vec![[255, 0, 0]; 2];
            row.push([9, 9, 9]);
            row.extend([[0, 0, 255]; 3]);
            row
        });
        assert_eq!(both.pixels[9], [9, 9, 9]);
    }

    #[test]
    fn placing_copies_and_cuts_off_at_the_edge() {
        let mut canvas = Image::filled(3, 2, [0, 0, 0]);
        canvas.place(&Image::filled(2, 2, [7, 7, 7]), 2, 1);
        assert_eq!(canvas.pixels[5], [7, 7, 7]);
        assert_eq!(canvas.pixels.iter().filter(|p| **p == [7, 7, 7]).count(), 1);
    }

    #[test]
    fn png_starts_with_the_signature() {
        let bytes = Image::filled(3, 2, [1, 2, 3]).png().unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    }
}
