//! Mutations of a glTF file, deterministic for a given random stream: byte-level ones (bit
//! flips, truncations, byte ranges and GLB chunks deleted or duplicated, length fields
//! rewritten) and JSON-aware ones (the JSON, or the GLB JSON chunk, parsed, changed and written
//! back: indices and counts out of range, types swapped, negative and huge numbers, node
//! cycles, fields removed or written twice).

use serde_json::{json, Value};

/// SplitMix64: small, fast and the same on every machine, so a seed names a run.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in 0..n (0 when n is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }

    pub fn chance(&mut self, one_in: usize) -> bool {
        self.below(one_in) == 0
    }

    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// One mutated file and what was done to it (for the report of a failing case).
pub struct Mutant {
    pub bytes: Vec<u8>,
    pub what: String,
}

/// A GLB split into its JSON text and the rest (BIN and any other chunks, raw).
struct Glb<'a> {
    json: &'a [u8],
    /// Chunks after the JSON one, each with its 8-byte header.
    rest: &'a [u8],
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

fn split_glb(bytes: &[u8]) -> Option<Glb<'_>> {
    if !bytes.starts_with(b"glTF") {
        return None;
    }
    let len = u32_at(bytes, 12)? as usize;
    let json = bytes.get(20..20 + len)?;
    let rest = bytes.get((20 + len).next_multiple_of(4)..)?;
    Some(Glb { json, rest })
}

/// A GLB of `json` and the raw chunks `rest`, every length field right.
fn join_glb(json: &[u8], rest: &[u8]) -> Vec<u8> {
    let mut chunk = json.to_vec();
    while chunk.len() % 4 != 0 {
        chunk.push(b' ');
    }
    let total = 12 + 8 + chunk.len() + rest.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&chunk);
    out.extend_from_slice(rest);
    out
}

/// (offset, total length with header) of each chunk of a GLB, as far as the lengths are sane.
fn glb_chunks(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut chunks = Vec::new();
    let mut at = 12;
    while let Some(len) = u32_at(bytes, at) {
        let total = 8 + len as usize;
        if at + total > bytes.len() {
            break;
        }
        chunks.push((at, total));
        at += total.next_multiple_of(4);
    }
    chunks
}

/// A mutant of `original`: one to three mutations of one kind, byte-level or JSON-aware.
pub fn mutate(original: &[u8], rng: &mut Rng) -> Mutant {
    if rng.below(10) < 6 {
        if let Some(m) = mutate_json(original, rng) {
            return m;
        }
    }
    mutate_bytes(original, rng)
}

const INTERESTING_U32: &[u32] =
    &[0, 1, 3, 4, 0x7f, 0xff, 0x100, 0xffff, 0x10000, 0x7fff_ffff, 0x8000_0000, 0xffff_fffc, 0xffff_ffff];

fn mutate_bytes(original: &[u8], rng: &mut Rng) -> Mutant {
    let mut bytes = original.to_vec();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(3) {
        let len = bytes.len();
        match rng.below(8) {
            0 | 1 => {
                let flips = 1 + rng.below(8);
                for _ in 0..flips {
                    if len > 0 {
                        let at = rng.below(len);
                        bytes[at] ^= 1 << rng.below(8);
                    }
                }
                what.push(format!("{flips} bit flips"));
            }
            2 => {
                let at = rng.below(len + 1);
                bytes.truncate(at);
                what.push(format!("truncated to {at}"));
            }
            3 => {
                let start = rng.below(len + 1);
                let end = (start + 1 + rng.below(256)).min(len);
                bytes.drain(start..end);
                what.push(format!("deleted bytes {start}..{end}"));
            }
            4 => {
                let start = rng.below(len + 1);
                let end = (start + 1 + rng.below(256)).min(len);
                let copy = bytes[start..end].to_vec();
                let at = rng.below(len + 1);
                bytes.splice(at..at, copy);
                what.push(format!("bytes {start}..{end} copied to {at}"));
            }
            5 => {
                // A length or count field (GLB header and chunk lengths sit at multiples of 4).
                let slots = len / 4;
                if slots > 0 {
                    let range = if rng.chance(2) { slots } else { slots.min(8) };
                    let at = 4 * rng.below(range);
                    let value = *rng.pick(INTERESTING_U32);
                    bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
                    what.push(format!("u32 at {at} set to {value:#x}"));
                }
            }
            _ => {
                let chunks = glb_chunks(&bytes);
                if chunks.is_empty() {
                    if len > 0 {
                        let at = rng.below(len);
                        bytes[at] = rng.next() as u8;
                        what.push(format!("byte {at} replaced"));
                    }
                    continue;
                }
                let (at, size) = *rng.pick(&chunks);
                let chunk = bytes[at..at + size.next_multiple_of(4).min(len - at)].to_vec();
                match rng.below(3) {
                    0 => {
                        bytes.drain(at..at + chunk.len());
                        what.push(format!("GLB chunk at {at} deleted"));
                    }
                    1 => {
                        bytes.splice(at..at, chunk);
                        what.push(format!("GLB chunk at {at} duplicated"));
                    }
                    _ => {
                        bytes.extend_from_slice(&chunk);
                        what.push(format!("GLB chunk at {at} appended"));
                    }
                }
                // Half the time the header's total length is kept right, so the chunks are read.
                if rng.chance(2) && bytes.len() >= 12 {
                    let total = bytes.len() as u32;
                    bytes[8..12].copy_from_slice(&total.to_le_bytes());
                }
            }
        }
    }
    Mutant { bytes, what: what.join(", ") }
}

/// Fields that index another array of the document, and the array.
const INDEX_FIELDS: &[(&str, &str)] = &[
    ("bufferView", "bufferViews"),
    ("buffer", "buffers"),
    ("indices", "accessors"),
    ("POSITION", "accessors"),
    ("NORMAL", "accessors"),
    ("TEXCOORD_0", "accessors"),
    ("JOINTS_0", "accessors"),
    ("WEIGHTS_0", "accessors"),
    ("COLOR_0", "accessors"),
    ("input", "accessors"),
    ("output", "accessors"),
    ("inverseBindMatrices", "accessors"),
    ("material", "materials"),
    ("mesh", "meshes"),
    ("skin", "skins"),
    ("camera", "cameras"),
    ("node", "nodes"),
    ("skeleton", "nodes"),
    ("scene", "scenes"),
    ("source", "images"),
    ("sampler", "samplers"),
    ("index", "textures"),
    ("light", "lights"),
];

const COUNT_FIELDS: &[&str] = &["count", "byteLength", "byteOffset", "byteStride"];

const TYPES: &[&str] = &["SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4", "VEC5", ""];
const COMPONENT_TYPES: &[i64] = &[5120, 5121, 5122, 5123, 5124, 5125, 5126, 0, -1];

fn interesting_number(rng: &mut Rng) -> Value {
    match rng.below(14) {
        0 => json!(-1),
        1 => json!(0),
        2 => json!(1),
        3 => json!(i64::MIN),
        4 => json!(u64::MAX),
        5 => json!(1u64 << 31),
        6 => json!((1u64 << 32) - 1),
        7 => json!(1u64 << 53),
        8 => json!(1e308),
        9 => json!(-1e308),
        10 => json!(0.5),
        11 => json!(-0.0),
        12 => json!(1e-45),
        _ => json!(rng.below(100_000)),
    }
}

/// A JSON pointer to every value in `v` (the root excluded), depth first.
fn pointers(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Object(map) => {
            for (k, child) in map {
                let p = format!("{at}/{}", k.replace('~', "~0").replace('/', "~1"));
                out.push(p.clone());
                pointers(child, p, out);
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                let p = format!("{at}/{i}");
                out.push(p.clone());
                pointers(child, p, out);
            }
        }
        _ => {}
    }
}

fn last_key(pointer: &str) -> &str {
    pointer.rsplit('/').next().unwrap_or("")
}

fn array_len(doc: &Value, name: &str) -> usize {
    let array = if name == "lights" { doc.pointer("/extensions/KHR_lights_punctual/lights") } else { doc.get(name) };
    array.and_then(Value::as_array).map_or(0, Vec::len)
}

/// Marks a key to be written twice: `write_json` turns `DUP:key` back into `key`.
const DUPLICATE_MARK: &str = "\u{1}DUP:";

fn mutate_json(original: &[u8], rng: &mut Rng) -> Option<Mutant> {
    let glb = split_glb(original);
    let text = glb.as_ref().map_or(original, |g| g.json);
    let mut doc: Value = serde_json::from_slice(text).ok()?;
    let mut what = Vec::new();
    // Mostly one change, so that most mutants get past the first check they break.
    let changes = if rng.chance(3) { 2 + rng.below(2) } else { 1 };
    for _ in 0..changes {
        let mut all = Vec::new();
        pointers(&doc, String::new(), &mut all);
        if all.is_empty() {
            break;
        }
        what.push(mutate_value(&mut doc, &all, rng));
    }
    let text = write_json(&doc);
    let bytes = match glb {
        Some(g) => join_glb(text.as_bytes(), g.rest),
        None => text.into_bytes(),
    };
    Some(Mutant { bytes, what: what.join(", ") })
}

/// The JSON text, each marked duplicate key written under its real name (after the original).
fn write_json(doc: &Value) -> String {
    let text = doc.to_string();
    text.replace("\"\\u0001DUP:", "\"")
}

fn mutate_value(doc: &mut Value, all: &[String], rng: &mut Rng) -> String {
    let kind = rng.below(10);
    // Targets of a kind, e.g. every `count`: mutations aim at them, or at anything at all.
    let with_key =
        |keys: &[&str]| -> Vec<String> { all.iter().filter(|p| keys.contains(&last_key(p))).cloned().collect() };
    match kind {
        0 | 1 => {
            let targets: Vec<(String, &str)> = all
                .iter()
                .filter_map(|p| INDEX_FIELDS.iter().find(|(k, _)| *k == last_key(p)).map(|(_, a)| (p.clone(), *a)))
                .collect();
            if targets.is_empty() {
                return mutate_any(doc, all, rng);
            }
            let (p, array) = rng.pick(&targets).clone();
            let n = array_len(doc, array);
            let value = match rng.below(4) {
                0 => json!(n),
                1 => json!(n + 1 + rng.below(1000)),
                2 => json!(rng.below(n.max(1))),
                _ => interesting_number(rng),
            };
            set(doc, &p, value.clone());
            format!("{p} = {value} (index into {array} of {n})")
        }
        2 => {
            let targets = with_key(COUNT_FIELDS);
            if targets.is_empty() {
                return mutate_any(doc, all, rng);
            }
            let p = rng.pick(&targets).clone();
            let old = doc.pointer(&p).and_then(Value::as_u64).unwrap_or(0);
            let value = match rng.below(5) {
                0 => json!(old.saturating_add(1)),
                1 => json!(old.saturating_mul(1000)),
                2 => json!(old.saturating_sub(1)),
                3 => json!(1u64 << (28 + rng.below(36))),
                _ => interesting_number(rng),
            };
            // A huge count with no buffer view: the zero-filled path.
            let mut note = String::new();
            if last_key(&p) == "count" && rng.chance(3) {
                let parent = &p[..p.len() - "/count".len()];
                if let Some(obj) = doc.pointer_mut(parent).and_then(Value::as_object_mut) {
                    obj.remove("bufferView");
                    note = " and its bufferView removed".into();
                }
            }
            set(doc, &p, value.clone());
            format!("{p} = {value}{note}")
        }
        3 => {
            let targets = with_key(&["type", "componentType", "mode", "interpolation", "path", "alphaMode"]);
            if targets.is_empty() {
                return mutate_any(doc, all, rng);
            }
            let p = rng.pick(&targets).clone();
            let value = match last_key(&p) {
                "type" => json!(rng.pick(TYPES)),
                "componentType" => json!(rng.pick(COMPONENT_TYPES)),
                "mode" => json!(rng.below(9)),
                _ => json!(rng.pick(&[
                    "LINEAR",
                    "STEP",
                    "CUBICSPLINE",
                    "translation",
                    "rotation",
                    "scale",
                    "weights",
                    "BLEND",
                    "?"
                ])),
            };
            set(doc, &p, value.clone());
            format!("{p} = {value}")
        }
        4 => {
            // A cycle: a node's child is itself, its parent, or another node's parent.
            let n = array_len(doc, "nodes");
            if n == 0 {
                return mutate_any(doc, all, rng);
            }
            let a = rng.below(n);
            let b = if rng.chance(3) { a } else { rng.below(n) };
            let Some(node) = doc.pointer_mut(&format!("/nodes/{a}")).and_then(Value::as_object_mut) else {
                return mutate_any(doc, all, rng);
            };
            let children = node.entry("children").or_insert_with(|| json!([]));
            if let Some(list) = children.as_array_mut() {
                list.push(json!(b));
            }
            // And b's child is a, closing the loop (when a != b).
            if a != b {
                if let Some(other) = doc.pointer_mut(&format!("/nodes/{b}")).and_then(Value::as_object_mut) {
                    if let Some(list) = other.entry("children").or_insert_with(|| json!([])).as_array_mut() {
                        list.push(json!(a));
                    }
                }
            }
            format!("node cycle {a} <-> {b}")
        }
        5 => {
            // A field removed.
            let p = rng.pick(all).clone();
            remove(doc, &p);
            format!("{p} removed")
        }
        6 => {
            // A field written twice, the second time with another value.
            let objects: Vec<&String> = all
                .iter()
                .filter(|p| doc.pointer(p).is_some_and(|v| v.as_object().is_some_and(|o| !o.is_empty())))
                .collect();
            if objects.is_empty() {
                return mutate_any(doc, all, rng);
            }
            let p = (*rng.pick(&objects)).clone();
            let value = interesting_number(rng);
            let Some(obj) = doc.pointer_mut(&p).and_then(Value::as_object_mut) else { return String::new() };
            let keys: Vec<String> = obj.keys().cloned().collect();
            let key = rng.pick(&keys).clone();
            obj.insert(format!("{DUPLICATE_MARK}{key}"), value.clone());
            format!("{p}/{key} written twice (second {value})")
        }
        7 => {
            // Negative and huge numbers anywhere a number is.
            let numbers: Vec<&String> = all.iter().filter(|p| doc.pointer(p).is_some_and(Value::is_number)).collect();
            if numbers.is_empty() {
                return mutate_any(doc, all, rng);
            }
            let p = (*rng.pick(&numbers)).clone();
            let value = interesting_number(rng);
            set(doc, &p, value.clone());
            format!("{p} = {value}")
        }
        8 => {
            // An array grown by copies of its own elements (many primitives, nodes, joints...).
            let arrays: Vec<&String> = all
                .iter()
                .filter(|p| doc.pointer(p).and_then(Value::as_array).is_some_and(|a| !a.is_empty()))
                .collect();
            if arrays.is_empty() {
                return mutate_any(doc, all, rng);
            }
            let p = (*rng.pick(&arrays)).clone();
            let copies = 1 + rng.below(300);
            if let Some(items) = doc.pointer_mut(&p).and_then(Value::as_array_mut) {
                let first = items[0].clone();
                items.extend(std::iter::repeat(first).take(copies));
            }
            format!("{p} grown by {copies} copies")
        }
        _ => mutate_any(doc, all, rng),
    }
}

/// Any value replaced by one of another JSON type.
fn mutate_any(doc: &mut Value, all: &[String], rng: &mut Rng) -> String {
    let p = rng.pick(all).clone();
    let value = match rng.below(7) {
        0 => json!(null),
        1 => json!(true),
        2 => json!("x"),
        3 => json!([]),
        4 => json!({}),
        5 => json!([1e308, -1e308, 0]),
        _ => interesting_number(rng),
    };
    set(doc, &p, value.clone());
    format!("{p} = {value}")
}

fn set(doc: &mut Value, pointer: &str, value: Value) {
    if let Some(slot) = doc.pointer_mut(pointer) {
        *slot = value;
    }
}

fn remove(doc: &mut Value, pointer: &str) {
    let Some((parent, key)) = pointer.rsplit_once('/') else { return };
    let key = key.replace("~1", "/").replace("~0", "~");
    match doc.pointer_mut(parent) {
        Some(Value::Object(map)) => {
            map.remove(&key);
        }
        Some(Value::Array(items)) => {
            if let Ok(i) = key.parse::<usize>() {
                if i < items.len() {
                    items.remove(i);
                }
            }
        }
        _ => {}
    }
}
