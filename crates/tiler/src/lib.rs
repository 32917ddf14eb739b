//! What a tile-based GPU moves, as nostencil's own profile and its fill-rate layer both count
//! it: render-pass attachments as data and their load/store traffic ([`attachment`]), the bytes
//! of each format ([`formats`]), and the memory traffic of a pass on a tiler and on an
//! immediate-mode GPU ([`bandwidth`]). Plain data and arithmetic: no device, no allocation.

pub mod attachment;
pub mod bandwidth;
pub mod formats;
