//! One atlas page for every model's shadow texture: each model's texture is a square tile of
//! the page, power-of-two sized and aligned to its own size (a buddy allocation), so that mip
//! level k of the page, restricted to a tile, is that tile's own mip k: a 2x2 box of an aligned
//! tile never reaches into its neighbour. One bake pass, one dilate pass and one mip chain then
//! serve every model, however many there are.

use crate::error::{Error, Result};

/// Where one model's shadow texture lies in the page, in texels of mip 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Tile {
    pub x: u32,
    pub y: u32,
    /// Its side: a power of two, and `x` and `y` are multiples of it.
    pub size: u32,
}

/// The page and every model's tile in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PageLayout {
    pub width: u32,
    pub height: u32,
    /// By the order of the sizes given to [`pack`].
    pub tiles: Vec<Tile>,
}

impl PageLayout {
    /// Texels of mip 0 the tiles cover (the rest of the page is never sampled).
    #[cfg(test)]
    pub fn tile_texels(&self) -> u64 {
        self.tiles.iter().map(|t| u64::from(t.size) * u64::from(t.size)).sum()
    }
}

/// Packs one square tile per entry of `sides` (powers of two) into the smallest page that holds
/// them: a square, or two squares side by side, a power of two a side. Larger tiles are placed
/// first, each in the first free aligned square of its size, splitting a larger free square into
/// quarters when none is left: with sides taken largest first this never leaves a gap a later
/// tile could have used, so the page is full to the last tile. `max_side`: the device's (and
/// the mobile profile's) largest image side.
pub fn pack(sides: &[u32], max_side: u32) -> Result<PageLayout> {
    if sides.is_empty() {
        return Err(Error::Internal("an atlas page of no tiles".into()));
    }
    if let Some(bad) = sides.iter().find(|s| !s.is_power_of_two()) {
        return Err(Error::Internal(format!("an atlas tile of side {bad}, not a power of two")));
    }
    let largest = sides.iter().copied().max().unwrap_or(1);
    let area: u64 = sides.iter().map(|&s| u64::from(s) * u64::from(s)).sum();
    // The smallest square side (a power of two, at least the largest tile) with area / 2 or more:
    // two such squares side by side hold every tile.
    let mut side = largest;
    while 2 * u64::from(side) * u64::from(side) < area {
        side *= 2;
    }
    let wide = u64::from(side) * u64::from(side) < area;
    let (width, height) = if wide { (2 * side, side) } else { (side, side) };
    if width > max_side || height > max_side {
        return Err(Error::InvalidInput(format!(
            "the models' shadow textures ({} tiles, {area} texels) need a {width}x{height} atlas page, and the \
             device allows {max_side} texels a side: lower --shadow-texture-size or use fewer models",
            sides.len()
        )));
    }
    // Free aligned squares, by side; each list in placement order (row by row, left to right).
    let mut free: Vec<Tile> = vec![Tile { x: 0, y: 0, size: side }];
    if wide {
        free.push(Tile { x: side, y: 0, size: side });
    }
    let mut order: Vec<usize> = (0..sides.len()).collect();
    // Largest first; equal sides in the order given, so a scene's models fill the page in order.
    order.sort_by(|&a, &b| sides[b].cmp(&sides[a]).then(a.cmp(&b)));
    let mut tiles = vec![Tile { x: 0, y: 0, size: 0 }; sides.len()];
    for index in order {
        let want = sides[index];
        // The smallest free square that holds the tile, first in placement order among equals.
        let pick = free
            .iter()
            .enumerate()
            .filter(|(_, f)| f.size >= want)
            .min_by_key(|(_, f)| (f.size, f.y, f.x))
            .map(|(i, _)| i)
            .ok_or_else(|| Error::Internal(format!("atlas page {width}x{height} full before its last tile")))?;
        let mut square = free.swap_remove(pick);
        while square.size > want {
            let half = square.size / 2;
            for (dx, dy) in [(half, 0), (0, half), (half, half)] {
                free.push(Tile { x: square.x + dx, y: square.y + dy, size: half });
            }
            square.size = half;
        }
        tiles[index] = square;
    }
    Ok(PageLayout { width, height, tiles })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_well_packed(layout: &PageLayout) {
        for (i, a) in layout.tiles.iter().enumerate() {
            assert!(a.size.is_power_of_two() && a.x % a.size == 0 && a.y % a.size == 0, "{a:?} unaligned");
            assert!(a.x + a.size <= layout.width && a.y + a.size <= layout.height, "{a:?} outside the page");
            for b in &layout.tiles[i + 1..] {
                let apart = a.x + a.size <= b.x || b.x + b.size <= a.x || a.y + a.size <= b.y || b.y + b.size <= a.y;
                assert!(apart, "{a:?} overlaps {b:?}");
            }
        }
    }

    #[test]
    fn table1_scenes_fill_their_pages() {
        // atlas-125: 125 tiles of 64 in 1024 x 512 (128 places), row by row.
        let layout = pack(&[64; 125], 4096).expect("pack");
        assert_eq!((layout.width, layout.height), (1024, 512));
        assert_well_packed(&layout);
        assert_eq!(layout.tile_texels(), 125 * 64 * 64);
        // atlas-one: the page is the one tile.
        let one = pack(&[256], 4096).expect("pack");
        assert_eq!((one.width, one.height, one.tiles[0]), (256, 256, Tile { x: 0, y: 0, size: 256 }));
    }

    #[test]
    fn mixed_sides_are_aligned_and_disjoint() {
        let sides = [16, 256, 64, 64, 128, 16, 32, 256, 4, 64];
        let layout = pack(&sides, 4096).expect("pack");
        assert_well_packed(&layout);
        for (tile, side) in layout.tiles.iter().zip(sides) {
            assert_eq!(tile.size, side);
        }
        // 2 x 256^2 + 128^2 + ... fits one 512 square.
        assert_eq!((layout.width, layout.height), (512, 512));
    }

    #[test]
    fn a_page_past_the_device_limit_is_refused_by_name() {
        let error = pack(&[4096, 4096, 4096], 4096).expect_err("too large").to_string();
        assert!(error.contains("8192x8192 atlas page") && error.contains("--shadow-texture-size"), "{error}");
        assert!(pack(&[48], 4096).is_err(), "not a power of two");
    }
}
