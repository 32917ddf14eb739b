//! Accessors copied out of their buffer views with checked offsets, strides and sparse
//! substitution. The gltf crate's own reader is not used: on a bad offset it returns `None`
//! (indistinguishable from a missing attribute), and it asserts or panics on wrong accessor
//! types, zero counts and short sparse data.

use gltf::json;
use json::accessor::{ComponentType, Type};

use super::buffers::Buffers;
use super::problem::Problem;

pub(super) fn type_name(t: Type) -> &'static str {
    match t {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

pub(super) fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    }
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn component_count(t: Type) -> usize {
    match t {
        Type::Scalar => 1,
        Type::Vec2 => 2,
        Type::Vec3 => 3,
        Type::Vec4 | Type::Mat2 => 4,
        Type::Mat3 => 9,
        Type::Mat4 => 16,
    }
}

/// An accessor copied out of its buffer view, with sparse substitution applied: `count`
/// elements of `components` values each, tightly packed (matrix column padding is not
/// supported, and matrices are only read as f32 MAT4).
pub(super) struct Dense {
    pub(super) ty: Type,
    pub(super) component: ComponentType,
    pub(super) normalized: bool,
    pub(super) count: usize,
    bytes: Vec<u8>,
}

impl Dense {
    pub(super) fn components(&self) -> usize {
        component_count(self.ty)
    }

    fn raw(&self, i: usize) -> Option<u32> {
        let size = component_size(self.component);
        let at = i.checked_mul(size)?;
        let b = self.bytes.get(at..at.checked_add(size)?)?;
        Some(match b {
            [a] => *a as u32,
            [a, b] => u16::from_le_bytes([*a, *b]) as u32,
            [a, b, c, d] => u32::from_le_bytes([*a, *b, *c, *d]),
            _ => return None,
        })
    }

    /// Component `i` (flat index) as f32, applying normalisation for integer types.
    pub(super) fn float(&self, i: usize) -> f32 {
        let Some(raw) = self.raw(i) else { return 0.0 };
        let n = self.normalized;
        match self.component {
            ComponentType::F32 => f32::from_bits(raw),
            ComponentType::I8 if n => (raw as u8 as i8 as f32 / 127.0).max(-1.0),
            ComponentType::U8 if n => raw as f32 / 255.0,
            ComponentType::I16 if n => (raw as u16 as i16 as f32 / 32767.0).max(-1.0),
            ComponentType::U16 if n => raw as f32 / 65535.0,
            ComponentType::I8 => raw as u8 as i8 as f32,
            ComponentType::I16 => raw as u16 as i16 as f32,
            _ => raw as f32,
        }
    }

    /// Component `i` (flat index) as an unsigned integer (integer component types only).
    pub(super) fn uint(&self, i: usize) -> u32 {
        self.raw(i).unwrap_or(0)
    }

    pub(super) fn floats(&self) -> Vec<f32> {
        (0..self.count * self.components()).map(|i| self.float(i)).collect()
    }

    pub(super) fn uints(&self) -> Vec<u32> {
        (0..self.count * self.components()).map(|i| self.uint(i)).collect()
    }
}

/// Copies `count` elements of `elem` bytes from `view` starting at `offset` with `stride`,
/// after checking they lie in `view` and charging their size to the file's read budget.
fn gather(
    buffers: &Buffers,
    view: &[u8],
    (offset, stride): (usize, usize),
    count: usize,
    elem: usize,
    out: &mut Vec<u8>,
) -> Result<(), Problem> {
    if count == 0 {
        return Ok(());
    }
    let last_start = (count - 1).checked_mul(stride).and_then(|x| x.checked_add(offset));
    let end = last_start.and_then(|x| x.checked_add(elem));
    match end {
        Some(end) if end <= view.len() => {}
        _ => {
            return Err(format!(
                "{count} elements of {elem} bytes (stride {stride}) from byteOffset {offset} run \
                 past the end of the {}-byte buffer view",
                view.len()
            ))
        }
    }
    buffers.charge_read(count * elem)?;
    out.reserve(count * elem);
    for k in 0..count {
        let at = offset + k * stride;
        let bytes = view.get(at..at + elem).ok_or_else(|| format!("element {k} is out of range of its buffer view"))?;
        out.extend_from_slice(bytes);
    }
    Ok(())
}

/// Copies accessor `index` into a `Dense`, checking its type against `types` and its component
/// type against `components` first. Errors say "accessor N ..." and what was expected.
pub(super) fn read_accessor(
    root: &json::Root,
    buffers: &Buffers,
    index: usize,
    types: &[Type],
    components: &[ComponentType],
) -> Result<Dense, Problem> {
    let accessor = root.accessors.get(index).ok_or_else(|| format!("accessor {index} does not exist"))?;
    let ty = match accessor.type_ {
        json::validation::Checked::Valid(t) => t,
        json::validation::Checked::Invalid => {
            return Err(format!("accessor {index}: `type` is none of SCALAR, VEC2-4, MAT2-4"))
        }
    };
    let component = match accessor.component_type {
        json::validation::Checked::Valid(c) => c.0,
        json::validation::Checked::Invalid => return Err(format!("accessor {index}: bad componentType")),
    };
    if !types.contains(&ty) {
        let expected: Vec<_> = types.iter().map(|t| type_name(*t)).collect();
        return Err(format!("accessor {index} has type {}, expected {}", type_name(ty), expected.join(" or ")));
    }
    if !components.contains(&component) {
        let expected: Vec<_> = components.iter().map(|c| component_name(*c)).collect();
        return Err(format!(
            "accessor {index} has componentType {}, expected {}",
            component_name(component),
            expected.join(" or ")
        ));
    }
    let count = usize::try_from(accessor.count.0)
        .map_err(|_| format!("accessor {index}: count {} is too large", accessor.count.0))?;
    if count == 0 {
        return Err(format!("accessor {index} has count 0"));
    }
    if matches!(ty, Type::Mat2 | Type::Mat3) && component_size(component) < 4 {
        return Err(format!(
            "accessor {index}: {} {} matrices (column padding) are not supported",
            component_name(component),
            type_name(ty)
        ));
    }
    let elem = component_size(component) * component_count(ty);
    let fail = |e: String| format!("accessor {index}: {e}");

    let mut bytes = Vec::new();
    match accessor.buffer_view {
        Some(view_index) => {
            let view_index = view_index.value();
            let view = buffers.view(view_index).map_err(fail)?;
            let stride = match root.buffer_views.get(view_index).and_then(|v| v.byte_stride) {
                Some(s) if s.0 != 0 => {
                    if s.0 < elem {
                        return Err(format!(
                            "accessor {index}: bufferView {view_index} byteStride {} is smaller \
                             than the {elem}-byte element",
                            s.0
                        ));
                    }
                    s.0
                }
                _ => elem,
            };
            let offset = usize::try_from(accessor.byte_offset.map_or(0, |o| o.0))
                .map_err(|_| fail("byteOffset is too large".into()))?;
            gather(buffers, view, (offset, stride), count, elem, &mut bytes)
                .map_err(|e| format!("accessor {index} in bufferView {view_index}: {e}"))?;
        }
        None => {
            // Zeros, as the spec defines an accessor without a bufferView (sparse values
            // may follow).
            let size = count
                .checked_mul(elem)
                .ok_or_else(|| fail(format!("{count} elements without a bufferView are too many")))?;
            bytes = buffers.zeroed(size).map_err(fail)?;
            buffers.charge_read(size).map_err(fail)?;
        }
    }

    if let Some(sparse) = &accessor.sparse {
        let sparse_count = usize::try_from(sparse.count.0)
            .ok()
            .filter(|&c| c >= 1 && c <= count)
            .ok_or_else(|| fail(format!("sparse count {} is not in 1..={count}", sparse.count.0)))?;
        let index_component = match sparse.indices.component_type {
            json::validation::Checked::Valid(c) => c.0,
            json::validation::Checked::Invalid => return Err(fail("bad sparse indices componentType".into())),
        };
        let index_size = component_size(index_component);
        if !matches!(index_component, ComponentType::U8 | ComponentType::U16 | ComponentType::U32) {
            return Err(fail(format!(
                "sparse indices have componentType {}, expected an unsigned type",
                component_name(index_component)
            )));
        }
        let iv = sparse.indices.buffer_view.value();
        let index_view = buffers.view(iv).map_err(fail)?;
        let mut index_bytes = Vec::new();
        let index_offset = usize::try_from(sparse.indices.byte_offset.0)
            .map_err(|_| fail("sparse indices byteOffset is too large".into()))?;
        gather(buffers, index_view, (index_offset, index_size), sparse_count, index_size, &mut index_bytes)
            .map_err(|e| fail(format!("sparse indices: {e}")))?;
        let vv = sparse.values.buffer_view.value();
        let value_view = buffers.view(vv).map_err(fail)?;
        let mut value_bytes = Vec::new();
        let value_offset = usize::try_from(sparse.values.byte_offset.0)
            .map_err(|_| fail("sparse values byteOffset is too large".into()))?;
        gather(buffers, value_view, (value_offset, elem), sparse_count, elem, &mut value_bytes)
            .map_err(|e| fail(format!("sparse values: {e}")))?;
        let indices = Dense {
            ty: Type::Scalar,
            component: index_component,
            normalized: false,
            count: sparse_count,
            bytes: index_bytes,
        };
        let mut previous: Option<usize> = None;
        for k in 0..sparse_count {
            let target = indices.uint(k) as usize;
            if target >= count || previous.is_some_and(|p| target <= p) {
                return Err(fail(format!(
                    "sparse index {k} is {target}: sparse indices must be strictly increasing \
                     and below the count {count}"
                )));
            }
            previous = Some(target);
            let (Some(dst), Some(src)) =
                (bytes.get_mut(target * elem..(target + 1) * elem), value_bytes.get(k * elem..(k + 1) * elem))
            else {
                return Err(fail(format!("sparse element {k} is out of range")));
            };
            dst.copy_from_slice(src);
        }
    }

    Ok(Dense { ty, component, normalized: accessor.normalized, count, bytes })
}
