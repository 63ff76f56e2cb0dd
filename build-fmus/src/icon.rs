//! `model.png`, the icon FMI 2.0 lets an FMU carry at its root (section 2.1.2): drawn here, in
//! code, from the model identifier, so it needs no file in the repository and the same
//! identifier gives the same bytes. A block with an input port on the left and an output port on
//! the right, in a colour hashed from the identifier, lettered with the identifier's capitals
//! (`RlcCircuit` -> "RC", up to three).

use std::io::Write;

use flate2::write::ZlibEncoder;
use flate2::Compression;

/// Width and height of the icon in pixels.
pub const SIZE: u32 = 128;

/// A 5x7 bitmap font for A-Z: seven rows per letter, the five low bits of each row, the
/// leftmost pixel in bit 4.
const GLYPHS: [[u8; 7]; 26] = [
    [0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11], // A
    [0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E], // B
    [0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E], // C
    [0x1E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1E], // D
    [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F], // E
    [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10], // F
    [0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F], // G
    [0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11], // H
    [0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E], // I
    [0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C], // J
    [0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11], // K
    [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F], // L
    [0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11], // M
    [0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11], // N
    [0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E], // O
    [0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10], // P
    [0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D], // Q
    [0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11], // R
    [0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E], // S
    [0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04], // T
    [0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E], // U
    [0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04], // V
    [0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A], // W
    [0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11], // X
    [0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04], // Y
    [0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F], // Z
];

/// The letters on the icon: the identifier's capitals (at most three), else its first letter.
pub fn initials(identifier: &str) -> String {
    let capitals: String = identifier.chars().filter(char::is_ascii_uppercase).take(3).collect();
    if !capitals.is_empty() {
        return capitals;
    }
    identifier.chars().find(char::is_ascii_alphabetic).map(|c| c.to_ascii_uppercase().to_string()).unwrap_or_default()
}

/// The block's colour: a hue hashed from the identifier (FNV-1a), muted and dark enough for
/// white letters.
fn colour(identifier: &str) -> [f64; 3] {
    let hash = identifier.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3));
    let hue = ((hash.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40) % 360) as f64 / 60.0;
    let (s, v) = (0.55, 0.62);
    let c = v * s;
    let x = c * (1.0 - (hue % 2.0 - 1.0).abs());
    let (r, g, b) = match hue as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r + m, g + m, b + m]
}

/// Whether (x, y) lies in the rectangle [x0, x1] x [y0, y1] with corners rounded by `r`.
fn in_rounded(x: f64, y: f64, (x0, y0, x1, y1): (f64, f64, f64, f64), r: f64) -> bool {
    if x < x0 || x > x1 || y < y0 || y > y1 {
        return false;
    }
    let dx = (x0 + r - x).max(x - (x1 - r)).max(0.0);
    let dy = (y0 + r - y).max(y - (y1 - r)).max(0.0);
    dx * dx + dy * dy <= r * r
}

/// The icon's colour at a point (in pixels), or None where it is transparent.
fn scene(x: f64, y: f64, fill: [f64; 3], letters: &[[u8; 7]], scale: f64) -> Option<[f64; 3]> {
    let s = SIZE as f64;
    let dark = fill.map(|c| c * 0.55);
    let block = (0.125 * s, 0.125 * s, 0.875 * s, 0.875 * s);
    let inner = (block.0 + 4.0, block.1 + 4.0, block.2 - 4.0, block.3 - 4.0);
    // The letters, centred on the block.
    let n = letters.len() as f64;
    let (w, h) = ((6.0 * n - 1.0) * scale, 7.0 * scale);
    let (lx, ly) = ((s - w) / 2.0, (s - h) / 2.0);
    if x >= lx && y >= ly && x < lx + w && y < ly + h {
        let (col, row) = (((x - lx) / scale) as usize, ((y - ly) / scale) as usize);
        let (letter, bit) = (col / 6, col % 6);
        if bit < 5 && letters[letter][row] & (0x10 >> bit) != 0 {
            return Some([1.0; 3]);
        }
    }
    if in_rounded(x, y, inner, 10.0) {
        return Some(fill);
    }
    if in_rounded(x, y, block, 14.0) {
        return Some(dark);
    }
    // The ports: an input on the left, an output on the right.
    let port = |x0: f64| x >= x0 && x <= x0 + 0.125 * s && (y - s / 2.0).abs() <= 0.05 * s;
    (port(0.02 * s) || port(0.855 * s)).then_some(dark)
}

/// The RGBA pixels of the icon, row by row: each pixel averages 4 x 4 samples of the scene, so
/// the rounded corners are smooth.
fn pixels(identifier: &str) -> Vec<u8> {
    let fill = colour(identifier);
    let letters: Vec<[u8; 7]> = initials(identifier).bytes().map(|c| GLYPHS[usize::from(c - b'A')]).collect();
    let scale = if letters.is_empty() { 1.0 } else { (84.0 / (6.0 * letters.len() as f64 - 1.0)).floor().min(10.0) };
    let mut rgba = Vec::with_capacity((SIZE * SIZE * 4) as usize);
    for py in 0..SIZE {
        for px in 0..SIZE {
            let (mut sum, mut covered) = ([0.0f64; 3], 0u32);
            for sy in 0..4 {
                for sx in 0..4 {
                    let (x, y) = (f64::from(px) + (f64::from(sx) + 0.5) / 4.0, f64::from(py) + (f64::from(sy) + 0.5) / 4.0);
                    if let Some(c) = scene(x, y, fill, &letters, scale) {
                        (0..3).for_each(|i| sum[i] += c[i]);
                        covered += 1;
                    }
                }
            }
            if covered == 0 {
                rgba.extend_from_slice(&[0, 0, 0, 0]);
            } else {
                let k = f64::from(covered);
                rgba.extend(sum.map(|c| (255.0 * c / k).round() as u8));
                rgba.push((255 * covered / 16) as u8);
            }
        }
    }
    rgba
}

/// One PNG chunk: length, type, data, CRC-32 of type and data.
fn chunk(png: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    png.extend_from_slice(&(data.len() as u32).to_be_bytes());
    png.extend_from_slice(kind);
    png.extend_from_slice(data);
    let mut crc = crc32fast::Hasher::new();
    crc.update(kind);
    crc.update(data);
    png.extend_from_slice(&crc.finalize().to_be_bytes());
}

/// The icon of `identifier` as PNG bytes: 128 x 128, 8-bit RGBA, not interlaced.
pub fn png(identifier: &str) -> Vec<u8> {
    let rgba = pixels(identifier);
    let row = (SIZE * 4) as usize;
    let mut raw = Vec::with_capacity(rgba.len() + SIZE as usize);
    for line in rgba.chunks(row) {
        raw.push(0); // filter type None
        raw.extend_from_slice(line);
    }
    let mut z = ZlibEncoder::new(Vec::new(), Compression::best());
    z.write_all(&raw).expect("writing to memory");
    let idat = z.finish().expect("writing to memory");
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&SIZE.to_be_bytes());
    ihdr.extend_from_slice(&SIZE.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]); // 8 bits, RGBA, deflate, adaptive filtering, no interlace
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    chunk(&mut png, b"IHDR", &ihdr);
    chunk(&mut png, b"IDAT", &idat);
    chunk(&mut png, b"IEND", &[]);
    png
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::read::ZlibDecoder;
    use std::io::Read;

    #[test]
    fn initials_are_the_capitals() {
        assert_eq!(initials("RlcCircuit"), "RC");
        assert_eq!(initials("TractionMotorThermal"), "TMT");
        assert_eq!(initials("MotorFanSystemWithMore"), "MFS");
        assert_eq!(initials("fan"), "F");
        assert_eq!(initials("_x1"), "X");
        assert_eq!(initials("_1"), "");
    }

    /// Splits a PNG into its chunks, checking each CRC.
    fn chunks(png: &[u8]) -> Vec<(String, Vec<u8>)> {
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let (mut at, mut out) = (8, Vec::new());
        while at < png.len() {
            let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
            let (kind, data) = (&png[at + 4..at + 8], &png[at + 8..at + 8 + len]);
            let crc = u32::from_be_bytes(png[at + 8 + len..at + 12 + len].try_into().unwrap());
            let mut h = crc32fast::Hasher::new();
            h.update(kind);
            h.update(data);
            assert_eq!(h.finalize(), crc);
            out.push((String::from_utf8(kind.to_vec()).unwrap(), data.to_vec()));
            at += 12 + len;
        }
        out
    }

    #[test]
    fn the_icon_is_a_valid_png_and_the_same_for_the_same_identifier() {
        let png_a = png("RlcCircuit");
        assert_eq!(png_a, png("RlcCircuit"));
        assert_ne!(png_a, png("MotorFan"));
        let parts = chunks(&png_a);
        let kinds: Vec<&str> = parts.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(kinds, ["IHDR", "IDAT", "IEND"]);
        assert_eq!(parts[0].1, [0, 0, 0, 128, 0, 0, 0, 128, 8, 6, 0, 0, 0]);
        let mut raw = Vec::new();
        ZlibDecoder::new(&parts[1].1[..]).read_to_end(&mut raw).unwrap();
        assert_eq!(raw.len(), (128 * (1 + 128 * 4)) as usize);
        assert_eq!(raw, {
            let mut r = Vec::new();
            for line in pixels("RlcCircuit").chunks(512) {
                r.push(0);
                r.extend_from_slice(line);
            }
            r
        });
        // Transparent corners, an opaque block, white letters somewhere on it.
        let px = pixels("RlcCircuit");
        let at = |x: usize, y: usize| &px[(y * 128 + x) * 4..(y * 128 + x) * 4 + 4];
        assert_eq!(at(0, 0), [0, 0, 0, 0]);
        assert_eq!(at(30, 30)[3], 255);
        assert!((0..128 * 128).any(|i| px[i * 4..i * 4 + 4] == [255, 255, 255, 255]));
        assert!(png_a.len() < 8000, "{} bytes", png_a.len());
    }
}
