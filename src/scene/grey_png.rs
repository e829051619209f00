//! Grey PNGs a scene names (a height map, a density mask): 8 or 16 bit,
//! read as values in 0..=1. The header is checked before anything is
//! decoded, so a file that declares an enormous image (a decompression
//! bomb) is refused without allocating it.

use std::io::{BufReader, Cursor, Read, Seek};
use std::path::Path;

use image::{ColorType, ImageDecoder, ImageReader, Limits};

/// The widest and tallest grey image read (16 M samples at most).
pub const MAX_SIDE: u32 = 4096;
/// The largest PNG file read.
const MAX_FILE_BYTES: u64 = 256 << 20;

/// A grey image: `width` x `height` values in 0..=1, row-major, row 0 first.
#[derive(Clone, Debug, PartialEq)]
pub struct Grey {
    pub width: u32,
    pub height: u32,
    pub values: Vec<f32>,
}

/// Reads the grey PNG at `path`; a refusal is what is wrong and the fix,
/// for the caller to put after the field and the file's name.
pub fn read(path: &Path) -> std::result::Result<Grey, String> {
    let size = std::fs::metadata(path)
        .map_err(|e| format!("cannot be read ({e}); give a path relative to the scene file"))?
        .len();
    if size > MAX_FILE_BYTES {
        return Err(format!(
            "{size} bytes is too large (at most {MAX_FILE_BYTES}); use a smaller image"
        ));
    }
    let file = std::fs::File::open(path)
        .map_err(|e| format!("cannot be read ({e}); give a path relative to the scene file"))?;
    decode(BufReader::new(file))
}

/// As `read`, from bytes in memory (the built-in scenes' images).
pub fn read_bytes(bytes: &[u8]) -> std::result::Result<Grey, String> {
    decode(Cursor::new(bytes))
}

fn decode<R: Read + Seek>(input: R) -> std::result::Result<Grey, String> {
    let not_png = |e: &dyn std::fmt::Display| {
        format!("is not a readable PNG ({e}); give an 8- or 16-bit grey PNG")
    };
    let mut reader = ImageReader::with_format(BufReader::new(input), image::ImageFormat::Png);
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    limits.max_alloc = Some(4 * MAX_SIDE as u64 * MAX_SIDE as u64);
    reader.limits(limits);
    let decoder = reader.into_decoder().map_err(|e| match e {
        image::ImageError::Limits(_) => format!(
            "its header declares an image larger than {MAX_SIDE} x {MAX_SIDE} pixels; use a smaller one"
        ),
        e => not_png(&e),
    })?;
    let (width, height) = decoder.dimensions();
    if width > MAX_SIDE || height > MAX_SIDE || width < 2 || height < 2 {
        return Err(format!(
            "{width} x {height} pixels is not allowed, use 2..={MAX_SIDE} pixels a side"
        ));
    }
    let color = decoder.color_type();
    let white = match color {
        ColorType::L8 => 255.0,
        ColorType::L16 => 65535.0,
        other => {
            return Err(format!(
                "is {other:?}, not grey; save it as an 8- or 16-bit greyscale PNG without alpha"
            ))
        }
    };
    let mut bytes = vec![0u8; decoder.total_bytes() as usize];
    decoder.read_image(&mut bytes).map_err(|e| not_png(&e))?;
    let values = match color {
        ColorType::L8 => bytes.iter().map(|&b| b as f32 / white).collect(),
        _ => bytes
            .chunks_exact(2)
            .map(|b| u16::from_ne_bytes([b[0], b[1]]) as f32 / white)
            .collect(),
    };
    Ok(Grey {
        width,
        height,
        values,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::ImageEncoder;

    fn png(width: u32, height: u32, color: image::ExtendedColorType, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        image::codecs::png::PngEncoder::new(&mut out)
            .write_image(data, width, height, color)
            .unwrap();
        out
    }

    /// `png` with its header's width and height set to `side`, the
    /// header's CRC-32 recomputed.
    pub fn declaring(mut png: Vec<u8>, side: u32) -> Vec<u8> {
        png[16..20].copy_from_slice(&side.to_be_bytes());
        png[20..24].copy_from_slice(&side.to_be_bytes());
        let crc = crc32(&png[12..29]);
        png[29..33].copy_from_slice(&crc.to_be_bytes());
        png
    }

    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = !0u32;
        for &b in bytes {
            c ^= b as u32;
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }

    #[test]
    fn eight_and_sixteen_bit_grey_read_as_fractions() {
        let g = read_bytes(&png(2, 2, image::ExtendedColorType::L8, &[0, 51, 255, 102])).unwrap();
        assert_eq!((g.width, g.height), (2, 2));
        assert_eq!(g.values, vec![0.0, 0.2, 1.0, 0.4]);
        let words: Vec<u8> = [0u16, 65535, 32768, 1]
            .iter()
            .flat_map(|w| w.to_ne_bytes())
            .collect();
        let g = read_bytes(&png(2, 2, image::ExtendedColorType::L16, &words)).unwrap();
        assert_eq!(g.values[1], 1.0);
        assert!((g.values[2] - 0.5).abs() < 1e-4);
    }

    #[test]
    fn colour_a_bomb_and_garbage_are_refused_in_one_line() {
        let rgb = png(2, 2, image::ExtendedColorType::Rgb8, &[0; 12]);
        let e = read_bytes(&rgb).unwrap_err();
        assert!(e.starts_with("is Rgb8, not grey"), "{e}");
        // A header declaring 100000 x 100000 pixels (its checksum right),
        // with 4 pixels of data behind it: refused from the header.
        let bomb = declaring(png(2, 2, image::ExtendedColorType::L8, &[0; 4]), 100_000);
        let e = read_bytes(&bomb).unwrap_err();
        assert!(
            e.contains("header declares an image larger than 4096 x 4096"),
            "{e}"
        );
        let mut cut = png(4, 4, image::ExtendedColorType::L8, &[7; 16]);
        cut.truncate(cut.len() - 20);
        let e = read_bytes(&cut).unwrap_err();
        assert!(e.contains("not a readable PNG") && !e.contains('\n'), "{e}");
        let e = read(Path::new("/nonexistent/h.png")).unwrap_err();
        assert!(
            e.contains("cannot be read") && e.contains("relative to the scene file"),
            "{e}"
        );
    }
}
