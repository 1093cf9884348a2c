//! `model.png`: the scene's drawing rasterized and written as a PNG (ISO/IEC 15948:2004,
//! "Portable Network Graphics (PNG) Specification (Second Edition)") without a compression
//! library: 8-bit palette colour, zlib stream of stored (uncompressed) deflate blocks
//! (RFC 1950, RFC 1951 section 3.2.4); the FMU's zip entry compresses it.

use super::svg::Fit;
use crate::model::Sketch;

/// Palette: background, frame, body lines.
const PALETTE: [[u8; 3]; 3] = [[255, 255, 255], [200, 200, 200], [31, 78, 156]];

/// A `size` × `size` icon of the drawing: a light frame and the body's lines, 2 px wide.
pub fn sketch_png(sketch: &Sketch, size: usize) -> Vec<u8> {
    let mut img = vec![0u8; size * size];
    for k in 0..size {
        for (x, y) in [(k, 0), (k, size - 1), (0, k), (size - 1, k)] {
            img[y * size + x] = 1;
        }
    }
    if let Some(fit) = Fit::new(sketch, size as f64, size as f64, 0.08 * size as f64) {
        for line in sketch.projected() {
            for seg in line.windows(2) {
                let (x0, y0) = fit.pixel(seg[0]);
                let (x1, y1) = fit.pixel(seg[1]);
                draw_segment(&mut img, size, (x0, y0), (x1, y1), 2);
            }
        }
    }
    encode_indexed(size, size, &PALETTE, &img)
}

/// Marks the pixels within a `width`-pixel square brush along the segment from `a` to `b`
/// (pixel coordinates) with colour index 2.
fn draw_segment(img: &mut [u8], size: usize, a: (f64, f64), b: (f64, f64), width: usize) {
    let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    let n = (2.0 * len).ceil().max(1.0) as usize;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
        for dx in 0..width {
            for dy in 0..width {
                let (px, py) = (x.floor() as i64 + dx as i64, y.floor() as i64 + dy as i64);
                if (0..size as i64).contains(&px) && (0..size as i64).contains(&py) {
                    img[py as usize * size + px as usize] = 2;
                }
            }
        }
    }
}

/// A PNG of `w` × `h` palette indices `pixels` (row by row) with the colours `palette`.
pub fn encode_indexed(w: usize, h: usize, palette: &[[u8; 3]], pixels: &[u8]) -> Vec<u8> {
    assert_eq!(pixels.len(), w * h, "one index per pixel");
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&(w as u32).to_be_bytes());
    ihdr.extend_from_slice(&(h as u32).to_be_bytes());
    // bit depth 8, colour type 3 (palette), deflate, adaptive filtering, no interlace
    ihdr.extend_from_slice(&[8, 3, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(&mut out, b"PLTE", &palette.concat());
    // every scanline with filter type 0 (None)
    let mut raw = Vec::with_capacity(h * (w + 1));
    for row in pixels.chunks(w) {
        raw.push(0);
        raw.extend_from_slice(row);
    }
    chunk(&mut out, b"IDAT", &zlib_stored(&raw));
    chunk(&mut out, b"IEND", &[]);
    out
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// A zlib stream (RFC 1950: CMF 0x78 = deflate with a 32 KiB window, FLG making the header a
/// multiple of 31) of stored deflate blocks of at most 65535 bytes (RFC 1951, 3.2.4), with
/// the Adler-32 checksum.
pub fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = if data.is_empty() {
        vec![&[]]
    } else {
        data.chunks(65535).collect()
    };
    for (k, b) in blocks.iter().enumerate() {
        out.push(u8::from(k + 1 == blocks.len())); // BFINAL, BTYPE = 00
        let len = b.len() as u16;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(b);
    }
    out.extend_from_slice(&adler32(data).to_be_bytes());
    out
}

/// Adler-32 (RFC 1950, section 9).
pub fn adler32(data: &[u8]) -> u32 {
    let (mut a, mut b) = (1u32, 0u32);
    for &x in data {
        a = (a + x as u32) % 65521;
        b = (b + a) % 65521;
    }
    (b << 16) | a
}

/// CRC-32 of PNG chunks and zip (ISO 3309, reflected polynomial 0xEDB88320; PNG
/// specification, annex D).
pub fn crc32(data: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &x in data {
        c ^= x as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksums_match_their_published_check_values() {
        // CRC-32 check value of "123456789" (the CRC catalogue's CRC-32/ISO-HDLC entry)
        assert_eq!(crc32(b"123456789"), 0xcbf4_3926);
        // Adler-32 of "Wikipedia", the worked example of the Adler-32 article
        assert_eq!(adler32(b"Wikipedia"), 0x11e6_0398);
    }

    #[test]
    fn the_zlib_header_and_stored_blocks_are_valid() {
        let data: Vec<u8> = (0..70000u32).map(|k| (k % 251) as u8).collect();
        let z = zlib_stored(&data);
        assert_eq!((u16::from(z[0]) << 8 | u16::from(z[1])) % 31, 0);
        // two blocks: 65535 + 4465 bytes, the second final
        assert_eq!(z[2], 0);
        assert_eq!(&z[3..5], &65535u16.to_le_bytes());
        let second = 2 + 5 + 65535;
        assert_eq!(z[second], 1);
        assert_eq!(&z[second + 1..second + 3], &4465u16.to_le_bytes());
        assert_eq!(z.len(), 2 + 5 + 65535 + 5 + 4465 + 4);
    }

    #[test]
    fn a_png_has_its_signature_chunks_and_crcs() {
        let png = encode_indexed(3, 2, &PALETTE, &[0, 1, 2, 2, 1, 0]);
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let mut pos = 8;
        let mut kinds = Vec::new();
        while pos < png.len() {
            let len = u32::from_be_bytes(png[pos..pos + 4].try_into().unwrap()) as usize;
            let body = &png[pos + 4..pos + 8 + len];
            let crc = u32::from_be_bytes(png[pos + 8 + len..pos + 12 + len].try_into().unwrap());
            assert_eq!(crc32(body), crc);
            kinds.push(String::from_utf8(body[..4].to_vec()).unwrap());
            pos += 12 + len;
        }
        assert_eq!(kinds, ["IHDR", "PLTE", "IDAT", "IEND"]);
        assert_eq!(pos, png.len());
    }
}
