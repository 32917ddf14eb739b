//! The tiler check's pattern: what a tile-based GPU would hand back for contents it was told it
//! need not keep, made conspicuous. A magenta and green checkerboard for colour (any channel the
//! program reads is 0 or full), 0.0 and 1.0 cells for depth and 0x00 and 0xff cells for stencil,
//! written with vkCmdClearAttachments inside the render pass (no image usage, layout or barrier
//! of the program's changes). Cells are 16 pixels, or an eighth of the area's shorter side when
//! that is more (8 cells along the shorter side), so the clear's rects stay few: lavapipe clears
//! them one by one.

use ash::vk;

/// The smallest side of a checkerboard cell, in pixels.
pub const CELL: u32 = 16;

/// The side of the checkerboard's cells over `area`.
pub fn cell_size(area: vk::Rect2D) -> u32 {
    CELL.max(area.extent.width.min(area.extent.height) / 8)
}

/// The clear value family of a colour format (a clear value is read by the format's type).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourClass {
    Float,
    Uint,
    Sint,
}

impl ColourClass {
    pub fn of(format: vk::Format) -> Self {
        let name = format!("{format:?}");
        if name.ends_with("_UINT") {
            ColourClass::Uint
        } else if name.ends_with("_SINT") {
            ColourClass::Sint
        } else {
            ColourClass::Float
        }
    }
}

/// One attachment to fill: a colour slot of the current subpass, or its depth/stencil aspects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Colour { slot: u32, class: ColourClass },
    DepthStencil { aspects: vk::ImageAspectFlags },
}

/// One vkCmdClearAttachments call.
#[derive(Clone)]
pub struct PoisonClear {
    pub attachments: Vec<vk::ClearAttachment>,
    pub rects: Vec<vk::ClearRect>,
}

impl std::fmt::Debug for PoisonClear {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PoisonClear({} attachments, {} rects)", self.attachments.len(), self.rects.len())
    }
}

fn value(target: Target, odd: bool) -> vk::ClearAttachment {
    match target {
        Target::Colour { slot, class } => {
            let colour = match class {
                ColourClass::Float => {
                    vk::ClearColorValue { float32: if odd { [0.0, 1.0, 0.0, 1.0] } else { [1.0, 0.0, 1.0, 1.0] } }
                }
                ColourClass::Uint => vk::ClearColorValue {
                    uint32: if odd { [0, u32::MAX, 0, u32::MAX] } else { [u32::MAX, 0, u32::MAX, u32::MAX] },
                },
                ColourClass::Sint => vk::ClearColorValue {
                    int32: if odd { [0, i32::MAX, 0, i32::MAX] } else { [i32::MAX, 0, i32::MAX, i32::MAX] },
                },
            };
            vk::ClearAttachment {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                color_attachment: slot,
                clear_value: vk::ClearValue { color: colour },
            }
        }
        Target::DepthStencil { aspects } => vk::ClearAttachment {
            aspect_mask: aspects,
            color_attachment: 0,
            clear_value: vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: if odd { 1.0 } else { 0.0 },
                    stencil: if odd { 0xff } else { 0 },
                },
            },
        },
    }
}

/// The checkerboard's odd cells inside `area`.
fn odd_cells(area: vk::Rect2D) -> Vec<vk::ClearRect> {
    let cell = cell_size(area);
    let (x0, y0) = (area.offset.x.max(0) as u32, area.offset.y.max(0) as u32);
    let (x1, y1) = (x0 + area.extent.width, y0 + area.extent.height);
    let mut rects = Vec::new();
    let mut y = y0;
    while y < y1 {
        let mut x = x0;
        while x < x1 {
            if ((x - x0) / cell + (y - y0) / cell) % 2 == 1 {
                rects.push(vk::ClearRect {
                    rect: vk::Rect2D {
                        offset: vk::Offset2D { x: x as i32, y: y as i32 },
                        extent: vk::Extent2D { width: cell.min(x1 - x), height: cell.min(y1 - y) },
                    },
                    base_array_layer: 0,
                    layer_count: 1,
                });
            }
            x += cell;
        }
        y += cell;
    }
    rects
}

/// The clears that fill `targets` with the pattern over `area`: the even colour everywhere,
/// then the odd one on every other cell.
pub fn pattern(targets: &[Target], area: vk::Rect2D) -> Vec<PoisonClear> {
    if targets.is_empty() || area.extent.width == 0 || area.extent.height == 0 {
        return Vec::new();
    }
    let whole = vk::ClearRect { rect: area, base_array_layer: 0, layer_count: 1 };
    let mut clears =
        vec![PoisonClear { attachments: targets.iter().map(|&t| value(t, false)).collect(), rects: vec![whole] }];
    let cells = odd_cells(area);
    if !cells.is_empty() {
        clears.push(PoisonClear { attachments: targets.iter().map(|&t| value(t, true)).collect(), rects: cells });
    }
    clears
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_checkerboard_covers_the_area_with_alternate_cells() {
        let area = vk::Rect2D { offset: vk::Offset2D { x: 8, y: 0 }, extent: vk::Extent2D { width: 40, height: 20 } };
        let clears = pattern(&[Target::Colour { slot: 1, class: ColourClass::Float }], area);
        assert_eq!(clears.len(), 2);
        assert_eq!(clears[0].rects[0].rect, area);
        // Cells (col, row): 3 x 2; odd ones are (1,0), (0,1), (2,1).
        let origins: Vec<(i32, i32, u32, u32)> = clears[1]
            .rects
            .iter()
            .map(|r| (r.rect.offset.x, r.rect.offset.y, r.rect.extent.width, r.rect.extent.height))
            .collect();
        assert_eq!(origins, vec![(24, 0, 16, 16), (8, 16, 16, 4), (40, 16, 8, 4)]);
        assert_eq!(clears[1].attachments[0].color_attachment, 1);
        // SAFETY: a float colour was written.
        assert_eq!(unsafe { clears[0].attachments[0].clear_value.color.float32 }, [1.0, 0.0, 1.0, 1.0]);
        assert_eq!(ColourClass::of(vk::Format::R8G8B8A8_UINT), ColourClass::Uint);
        assert_eq!(ColourClass::of(vk::Format::R16_SINT), ColourClass::Sint);
        assert_eq!(ColourClass::of(vk::Format::B8G8R8A8_SRGB), ColourClass::Float);
        assert!(pattern(&[], area).is_empty());
        // A large area: cells an eighth of its shorter side, 10 x 8 of them.
        let large = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width: 500, height: 400 } };
        assert_eq!(cell_size(large), 50);
        assert_eq!(pattern(&[Target::DepthStencil { aspects: vk::ImageAspectFlags::DEPTH }], large)[1].rects.len(), 40);
    }
}
