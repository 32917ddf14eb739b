//! The overdraw heat map: fragments shaded per pixel, counted on the GPU in the alpha channel
//! (every pipeline of the frame replaced by an `ADD ONE ONE` counter of 1/255), drawn as a
//! colour ramp with a legend of numbered swatches. At N samples per pixel the counter is blended
//! in every covered sample and the resolve averages them: a pixel's count is the mean over its
//! samples (rounded), so n full-screen layers read n at any N, and an edge pixel half covered by
//! one more layer reads between.

use image::{Rgba, RgbaImage};

/// Colours for counts 0, 1, 2, ...; the last one is used for everything above.
const RAMP: [[u8; 3]; 11] = [
    [12, 12, 40],    // 0: nothing shaded
    [40, 60, 170],   // 1
    [30, 140, 220],  // 2
    [30, 190, 160],  // 3
    [90, 200, 70],   // 4
    [200, 220, 50],  // 5
    [250, 180, 40],  // 6
    [245, 120, 30],  // 7
    [225, 60, 30],   // 8
    [180, 20, 60],   // 9
    [255, 255, 255], // 10 and more
];

pub fn colour_of(count: u8) -> [u8; 3] {
    RAMP[(count as usize).min(RAMP.len() - 1)]
}

/// Counts per ramp colour: 1 while the frame's largest count fits the ramp, else wider bins so
/// that the whole range stays readable (a frame of 12 full-screen passes is not all "10+").
pub fn bin_width(max_count: u8) -> u32 {
    (max_count as u32 + 1).div_ceil(RAMP.len() as u32 - 1).max(1)
}

/// Per-pixel counts from a frame rendered with overdraw counting (its alpha channel).
pub fn counts(frame: &RgbaImage) -> Vec<u8> {
    frame.pixels().map(|p| p[3]).collect()
}

const LEGEND_HEIGHT: u32 = 34;

/// The heat map with a legend strip under it: one swatch per count up to the frame's largest
/// (10+ shares the last colour), each numbered, and the caption "FRAGMENTS PER PIXEL".
pub fn render_heatmap(frame: &RgbaImage) -> RgbaImage {
    let counts = counts(frame);
    let (width, height) = (frame.width().max(320), frame.height() + LEGEND_HEIGHT);
    let mut out = RgbaImage::new(width, height);
    let put = |out: &mut RgbaImage, x: u32, y: u32, c: [u8; 3]| {
        if x < out.width() && y < out.height() {
            out.put_pixel(x, y, Rgba([c[0], c[1], c[2], 255]));
        }
    };
    for y in 0..height {
        for x in 0..width {
            put(&mut out, x, y, [24, 24, 24]);
        }
    }
    let max_count = counts.iter().copied().max().unwrap_or(0);
    let bin = bin_width(max_count);
    let index = |count: u8| (count as u32).div_ceil(bin).min(RAMP.len() as u32 - 1) as u8;
    for y in 0..frame.height() {
        for x in 0..frame.width() {
            put(&mut out, x, y, colour_of(index(counts[(y * frame.width() + x) as usize])));
        }
    }
    let max = index(max_count);
    let swatch = 10u32;
    let top = frame.height() + 4;
    let spacing = if bin == 1 { swatch + 8 } else { swatch + 20 };
    for n in 0..=max {
        let x0 = 4 + n as u32 * spacing;
        for y in top..top + swatch {
            for x in x0..x0 + swatch {
                put(&mut out, x, y, colour_of(n));
            }
        }
        // Swatch n covers counts ((n-1)*bin, n*bin]; label it with its upper end.
        let upper = n as u32 * bin;
        let label = if bin == 1 && n as usize == RAMP.len() - 1 { format!("{n}+") } else { upper.to_string() };
        draw_text(&mut out, x0, top + swatch + 3, &label, [230, 230, 230]);
    }
    let caption = "FRAGMENTS PER PIXEL";
    let caption_x = width.saturating_sub(caption.len() as u32 * 6 + 4);
    draw_text(&mut out, caption_x.max(4 + (max as u32 + 1) * spacing), top + 2, caption, [230, 230, 230]);
    out
}

/// 5x7 glyphs, one row per byte (low 5 bits, bit 4 = leftmost column).
fn glyph(c: char) -> [u8; 7] {
    match c {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '+' => [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00],
        'A' => [0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'E' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F],
        'F' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10],
        'G' => [0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F],
        'I' => [0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E],
        'L' => [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F],
        'M' => [0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11],
        'N' => [0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11],
        'P' => [0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10],
        'R' => [0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11],
        'S' => [0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E],
        'T' => [0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04],
        'X' => [0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11],
        _ => [0; 7],
    }
}

pub fn draw_text(image: &mut RgbaImage, x: u32, y: u32, text: &str, colour: [u8; 3]) {
    for (i, c) in text.chars().enumerate() {
        let rows = glyph(c);
        for (dy, row) in rows.iter().enumerate() {
            for dx in 0..5u32 {
                if row & (0x10 >> dx) != 0 {
                    let (px, py) = (x + i as u32 * 6 + dx, y + dy as u32);
                    if px < image.width() && py < image.height() {
                        image.put_pixel(px, py, Rgba([colour[0], colour[1], colour[2], 255]));
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_map_to_distinct_colours_and_the_legend_is_below_the_frame() {
        let mut frame = RgbaImage::new(330, 20);
        for (i, p) in frame.pixels_mut().enumerate() {
            p[3] = (i % 10) as u8;
        }
        let map = render_heatmap(&frame);
        assert_eq!(map.dimensions(), (330, 20 + LEGEND_HEIGHT));
        assert_eq!(bin_width(9), 1);
        assert_eq!(bin_width(10), 2);
        assert_eq!(bin_width(29), 3);
        let distinct: std::collections::HashSet<[u8; 3]> = RAMP.iter().copied().collect();
        assert_eq!(distinct.len(), RAMP.len());
        assert_eq!(map.get_pixel(3, 0).0[..3], colour_of(3));
        assert_eq!(colour_of(200), colour_of(10));
    }
}
