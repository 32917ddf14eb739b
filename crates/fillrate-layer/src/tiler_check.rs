//! The tiler check's verdicts (`NOSTENCIL_FILLRATE_TILER=1`, `profile-app --tiler-check`): what
//! the command stream does with each render pass's attachments, read in submission order, and
//! the load/store mistakes a tile-based GPU punishes but lavapipe or a desktop GPU forgive.
//! Pure bookkeeping over [`Event`]s (the hooks in image_use.rs and commands.rs make them), so it
//! is tested without a GPU.
//!
//! A stored attachment must be read (loaded by a later pass, copied, blitted, resolved or
//! sampled by a draw or dispatch) before it is cleared or overwritten, and by the end of the
//! frame after the one that stored it (a history buffer read one frame later is fine). Images the
//! layer did not see created (swapchain images) are presented: always read.

use std::collections::HashMap;

pub use nostencil_fillrate_report::tiler::{PoisonNote, TilerFlag, TilerReport};

/// One subresource an attachment view names: the image (raw handle), mip level and layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ImageKey {
    pub image: u64,
    pub mip: u32,
    pub layer: u32,
}

/// What a pass does with an attachment's old contents.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Load {
    /// LOAD from a defined layout: the old contents are read.
    Load,
    Clear,
    /// DONT_CARE, or LOAD from the UNDEFINED layout: a tiler hands back garbage.
    DontCare,
    /// LOAD_OP_NONE: kept, not read.
    Keep,
}

/// What a pass does with an attachment's new contents.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Store {
    Store,
    DontCare,
    /// STORE_OP_NONE: left as they were before the pass.
    Keep,
}

/// One attachment of a render pass instance as the check sees it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PassAttachment {
    /// Role, index and format, e.g. "colour #0 (R8G8B8A8_UNORM)".
    pub name: String,
    /// None for a view the layer did not see created.
    pub key: Option<ImageKey>,
    pub samples: u32,
    pub load: Load,
    pub store: Store,
    /// The render area covers the whole view: a CLEAR or DONT_CARE load replaces all of it.
    pub covers_image: bool,
    /// An image the layer did not see created (a swapchain image): presented, always read.
    pub external: bool,
    /// Filled with the pattern right after the pass began / right before it ended.
    pub poisoned_before: bool,
    pub poisoned_after: bool,
}

/// What the command stream did, in submission order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Event {
    PassBegin {
        label: Option<String>,
        attachments: Vec<PassAttachment>,
    },
    /// The pass's first draw read attachment `attachment` (index in the pass's list) although
    /// it was loaded DONT_CARE: `how` (blending, a partial write mask, a depth test).
    ReadUndefined {
        attachment: usize,
        how: &'static str,
    },
    PassEnd,
    /// Outside a pass: `image` read by `how` (a copy, a blit, a sampled draw).
    Read {
        image: u64,
        how: &'static str,
        transient: bool,
    },
    /// Outside a pass: `image` written by `how`; `full`: all of it.
    Overwrite {
        image: u64,
        how: &'static str,
        full: bool,
        transient: bool,
    },
    /// vkCmdClearColorImage or vkCmdClearDepthStencilImage (`how`) of `image`'s mips and layers
    /// in `ranges` (end u32::MAX: the remaining ones). On a tiler the clear is written to
    /// memory, and a pass that loads it reads it back.
    Cleared {
        image: u64,
        how: &'static str,
        ranges: Vec<(std::ops::Range<u32>, std::ops::Range<u32>)>,
    },
    /// vkCmdResolveImage from `src` into `dst`.
    Resolve {
        src: u64,
        dst: u64,
        src_transient: bool,
        dst_transient: bool,
    },
}

/// Where an attachment's contents came from.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Origin {
    frame: u64,
    pass: u32,
    label: Option<String>,
    attachment: String,
    samples: u32,
    /// The pass's record in `passes`.
    record: usize,
    /// Its "after the pass" poison note, if it was poisoned.
    note: Option<usize>,
}

#[derive(Debug, Default)]
struct ImageState {
    /// Stored by a pass and not yet read.
    unread: Option<Origin>,
    /// Left DONT_CARE by a pass, not rewritten since.
    discarded: Option<Origin>,
}

/// A vkCmdClear*Image not yet followed by another use of the image.
#[derive(Debug)]
struct ClearRecord {
    image: u64,
    how: &'static str,
    ranges: Vec<(std::ops::Range<u32>, std::ops::Range<u32>)>,
    used: Vec<ImageKey>,
}

impl ClearRecord {
    fn covers(&self, key: ImageKey) -> bool {
        key.image == self.image
            && !self.used.contains(&key)
            && self.ranges.iter().any(|(mips, layers)| mips.contains(&key.mip) && layers.contains(&key.layer))
    }
}

/// A pass whose stored outputs are still waiting to be read or found unread.
#[derive(Debug)]
struct PassRecord {
    frame: u64,
    pass: u32,
    label: Option<String>,
    pending: u32,
    read_any: bool,
}

#[derive(Debug)]
struct OpenPass {
    pass: u32,
    label: Option<String>,
    attachments: Vec<PassAttachment>,
    record: usize,
    /// Each attachment's "before the pass" poison note.
    notes: Vec<Option<usize>>,
}

/// The check's state over the whole run.
#[derive(Debug, Default)]
pub struct TilerCheck {
    frame: u64,
    /// Passes begun in this frame.
    position: u32,
    open: Option<OpenPass>,
    images: HashMap<ImageKey, ImageState>,
    /// Passes with outputs still waiting, by id (dropped once all are settled).
    passes: HashMap<usize, PassRecord>,
    /// Clear commands whose result no pass has used yet: image, what cleared it, its ranges,
    /// and the subresources a pass has used since.
    clears: Vec<ClearRecord>,
    /// The colour attachments the last pass ended stored: what a GL buffer swap shows.
    last_colours: Vec<ImageKey>,
    next_record: usize,
    report: TilerReport,
}

fn pass_name(pass: u32, label: &Option<String>) -> String {
    match label {
        Some(label) => format!("pass #{pass} '{label}'"),
        None => format!("pass #{pass}"),
    }
}

impl TilerCheck {
    pub fn report(&self) -> TilerReport {
        self.report.clone()
    }

    pub fn process(&mut self, events: &[Event]) {
        for event in events {
            self.event(event);
        }
    }

    /// Reads the layer cannot follow: the flags that need every read are no longer given.
    pub fn reads_unknown(&mut self, why: &str) {
        self.report.reads_unknown.get_or_insert_with(|| why.to_owned());
    }

    fn flag(&mut self, kind: &str, origin: (u64, u32, &Option<String>), attachment: Option<&str>, detail: String) {
        let needs_reads = matches!(kind, "stored_never_read" | "dead_pass" | "stored_then_overwritten");
        if needs_reads && self.report.reads_unknown.is_some() {
            return;
        }
        let (frame, pass, label) = origin;
        let same = |f: &TilerFlag| {
            f.kind == kind && f.pass == pass && f.label == *label && f.attachment.as_deref() == attachment
        };
        self.count_or_add(
            same,
            TilerFlag {
                kind: kind.to_owned(),
                frame,
                pass,
                label: label.clone(),
                attachment: attachment.map(str::to_owned),
                detail,
                count: 1,
                work: None,
            },
        );
    }

    /// One more of the flag `same` finds (the same mistake again), or `flag` as the first.
    fn count_or_add(&mut self, same: impl Fn(&TilerFlag) -> bool, flag: TilerFlag) {
        match self.report.flags.iter_mut().find(|f| same(f)) {
            Some(found) => found.count += 1,
            None => self.report.flags.push(flag),
        }
    }

    /// A copy or blit that writes a whole swapchain image (work row `work` of `frame`): the
    /// frame went through system memory once more to reach the screen.
    pub fn swapchain_copy(&mut self, frame: u64, work: u32, label: &Option<String>, detail: &str) {
        let kind = "full_frame_copy_to_swapchain";
        let same = |f: &TilerFlag| f.kind == kind && f.work == Some(work) && f.label == *label;
        self.count_or_add(
            same,
            TilerFlag {
                kind: kind.to_owned(),
                frame,
                pass: 0,
                label: label.clone(),
                attachment: None,
                detail: format!("{detail}; render the last pass into the swapchain image instead"),
                count: 1,
                work: Some(work),
            },
        );
    }

    fn note(&mut self, when: &str, pass: u32, label: &Option<String>, attachment: &str) -> usize {
        let same = |n: &PoisonNote| n.when == when && n.pass == pass && n.label == *label && n.attachment == attachment;
        if let Some(index) = self.report.poisoned.iter().position(same) {
            self.report.poisoned[index].count += 1;
            return index;
        }
        self.report.poisoned.push(PoisonNote {
            when: when.to_owned(),
            frame: self.frame,
            pass,
            label: label.clone(),
            attachment: attachment.to_owned(),
            read_by: None,
            count: 1,
        });
        self.report.poisoned.len() - 1
    }

    fn pattern_read(&mut self, note: Option<usize>, by: String) {
        if let Some(note) = note.and_then(|n| self.report.poisoned.get_mut(n)) {
            note.read_by.get_or_insert(by);
        }
    }

    fn event(&mut self, event: &Event) {
        match event {
            Event::PassBegin { label, attachments } => self.pass_begin(label.clone(), attachments.clone()),
            Event::ReadUndefined { attachment, how } => self.read_undefined(*attachment, how),
            Event::PassEnd => self.pass_end(),
            Event::Read { image, how, transient } => {
                self.clears.retain(|c| c.image != *image);
                self.outside_pass(*image, *transient, how);
                self.read(*image, how);
            }
            Event::Overwrite { image, how, full, transient } => {
                self.clears.retain(|c| c.image != *image);
                self.outside_pass(*image, *transient, how);
                self.overwrite(*image, how, *full);
            }
            Event::Cleared { image, how, ranges } => {
                self.clears.retain(|c| c.image != *image);
                self.clears.push(ClearRecord { image: *image, how, ranges: ranges.clone(), used: Vec::new() });
            }
            Event::Resolve { src, dst, src_transient, dst_transient } => {
                self.clears.retain(|c| c.image != *src && c.image != *dst);
                self.outside_pass(*src, *src_transient, "vkCmdResolveImage");
                self.outside_pass(*dst, *dst_transient, "vkCmdResolveImage");
                let multisampled: Vec<Origin> = self
                    .images
                    .iter()
                    .filter(|(k, s)| k.image == *src && s.unread.as_ref().is_some_and(|o| o.samples > 1))
                    .filter_map(|(_, s)| s.unread.clone())
                    .collect();
                for o in multisampled {
                    let detail = format!(
                        "{} x{} stored by {} and resolved by vkCmdResolveImage: a resolve attachment in the pass \
                         would resolve it in tile memory and store one sample",
                        o.attachment,
                        o.samples,
                        pass_name(o.pass, &o.label)
                    );
                    self.flag("resolve_outside_pass", (o.frame, o.pass, &o.label), Some(&o.attachment), detail);
                }
                self.read(*src, "vkCmdResolveImage");
                self.overwrite(*dst, "vkCmdResolveImage", false);
            }
        }
    }

    fn pass_begin(&mut self, label: Option<String>, attachments: Vec<PassAttachment>) {
        let pass = self.position;
        self.position += 1;
        let here = pass_name(pass, &label);
        let record = self.next_record;
        self.next_record += 1;
        self.passes
            .insert(record, PassRecord { frame: self.frame, pass, label: label.clone(), pending: 0, read_any: false });
        let mut notes = Vec::new();
        for a in &attachments {
            notes.push(a.poisoned_before.then(|| self.note("before the pass (DONT_CARE load)", pass, &label, &a.name)));
            if a.samples > 1 && a.store == Store::Store {
                let detail = format!(
                    "{} has {} samples and is stored: every sample leaves tile memory; store DONT_CARE and resolve \
                     in the pass",
                    a.name, a.samples
                );
                self.flag("multisampled_stored", (self.frame, pass, &label), Some(&a.name), detail);
            }
            let Some(key) = a.key else { continue };
            self.after_clear_command(key, a, (pass, &label));
            if a.load == Load::Load {
                let detail = format!(
                    "{here} loads {} (LOAD_OP_LOAD): a tiler reads it from memory into tile memory before the pass; \
                     clear it in the pass or leave it DONT_CARE where its old contents are not needed",
                    a.name
                );
                self.flag("attachment_loaded", (self.frame, pass, &label), Some(&a.name), detail);
            }
            match a.load {
                Load::Load => {
                    let discarded = self.images.get(&key).and_then(|s| s.discarded.clone());
                    if let Some(o) = discarded {
                        let detail = format!(
                            "{here} loads {} which {} left DONT_CARE: on a tiler it holds garbage",
                            a.name,
                            pass_name(o.pass, &o.label)
                        );
                        self.flag("load_after_dont_care", (self.frame, pass, &label), Some(&a.name), detail);
                        self.pattern_read(o.note, format!("{here}'s LOAD"));
                    }
                    self.read_key(key);
                }
                Load::Clear | Load::DontCare => {
                    if a.covers_image {
                        let how = if a.load == Load::Clear { "cleared" } else { "not loaded (DONT_CARE)" };
                        self.replaced(key, &format!("{how} by {here}"));
                    }
                    if let Some(state) = self.images.get_mut(&key) {
                        state.discarded = None;
                    }
                }
                Load::Keep => {}
            }
        }
        self.open = Some(OpenPass { pass, label, attachments, record, notes });
    }

    /// An attachment a clear command cleared and nothing used since: loading it reads the clear
    /// back from memory, clearing it again wastes the first clear (Arm's "inefficient clear" and
    /// "redundant clear").
    fn after_clear_command(&mut self, key: ImageKey, a: &PassAttachment, (pass, label): (u32, &Option<String>)) {
        let Some(clear) = self.clears.iter_mut().find(|c| c.covers(key)) else { return };
        clear.used.push(key);
        let (how, here) = (clear.how, pass_name(pass, label));
        let (kind, detail) = match a.load {
            Load::Load => (
                "clear_then_load",
                format!(
                    "{} is cleared by {how}, then loaded by {here}: the clear is written to memory and read back; \
                     clear it with LOAD_OP_CLEAR in the pass instead",
                    a.name
                ),
            ),
            Load::Clear => (
                "redundant_clear",
                format!(
                    "{} is cleared by {how}, then cleared again by {here}'s LOAD_OP_CLEAR: the first clear only \
                     moves bytes",
                    a.name
                ),
            ),
            Load::DontCare => (
                "redundant_clear",
                format!("{} is cleared by {how}, then {here} loads it DONT_CARE: the clear is lost", a.name),
            ),
            Load::Keep => return,
        };
        self.flag(kind, (self.frame, pass, label), Some(&a.name), detail);
    }

    fn read_undefined(&mut self, index: usize, how: &str) {
        let Some(open) = &self.open else { return };
        let Some(a) = open.attachments.get(index) else { return };
        let (pass, label, name, note) = (open.pass, open.label.clone(), a.name.clone(), open.notes[index]);
        let detail = format!(
            "{} is loaded DONT_CARE, then the pass's first draw reads it ({how}): a tiler hands back garbage",
            name
        );
        self.flag("dont_care_load_read", (self.frame, pass, &label), Some(&name), detail);
        self.pattern_read(note, format!("the pass's first draw ({how})"));
    }

    fn pass_end(&mut self) {
        let Some(open) = self.open.take() else { return };
        self.last_colours = open
            .attachments
            .iter()
            .filter(|a| a.store == Store::Store && a.name.starts_with("colour"))
            .filter_map(|a| a.key)
            .collect();
        for a in &open.attachments {
            let note = a
                .poisoned_after
                .then(|| self.note("after the pass (DONT_CARE store)", open.pass, &open.label, &a.name));
            let Some(key) = a.key else { continue };
            let origin = Origin {
                frame: self.frame,
                pass: open.pass,
                label: open.label.clone(),
                attachment: a.name.clone(),
                samples: a.samples,
                record: open.record,
                note,
            };
            match a.store {
                Store::Store if a.external => {
                    // Presented: read, so the pass that drew it is alive whatever else it stores.
                    self.images.remove(&key);
                    if let Some(record) = self.passes.get_mut(&open.record) {
                        record.read_any = true;
                    }
                }
                Store::Store => {
                    if let Some(record) = self.passes.get_mut(&open.record) {
                        record.pending += 1;
                    }
                    let state = self.images.entry(key).or_default();
                    state.discarded = None;
                    state.unread = Some(origin);
                }
                Store::DontCare => {
                    let state = self.images.entry(key).or_default();
                    state.discarded = Some(origin);
                }
                Store::Keep => {}
            }
        }
        if self.passes.get(&open.record).is_some_and(|r| r.pending == 0) {
            self.passes.remove(&open.record);
        }
    }

    /// A subresource's stored contents are read: its pass is alive.
    fn read_key(&mut self, key: ImageKey) {
        if let Some(o) = self.images.get_mut(&key).and_then(|s| s.unread.take()) {
            if let Some(record) = self.passes.get_mut(&o.record) {
                record.read_any = true;
                record.pending = record.pending.saturating_sub(1);
                if record.pending == 0 {
                    self.passes.remove(&o.record);
                }
            }
        }
    }

    fn read(&mut self, image: u64, how: &str) {
        // The open pass's own attachments are read in tile memory (input attachments).
        let own: Vec<ImageKey> = self.open.iter().flat_map(|p| p.attachments.iter().filter_map(|a| a.key)).collect();
        let keys: Vec<ImageKey> =
            self.images.keys().filter(|k| k.image == image && !own.contains(k)).copied().collect();
        for key in keys {
            if let Some(o) = self.images.get(&key).and_then(|s| s.discarded.clone()) {
                let detail = format!(
                    "{} was left DONT_CARE by {}, then read by {how}: on a tiler it holds garbage",
                    o.attachment,
                    pass_name(o.pass, &o.label)
                );
                self.flag("load_after_dont_care", (o.frame, o.pass, &o.label), Some(&o.attachment), detail);
                self.pattern_read(o.note, how.to_owned());
            }
            self.read_key(key);
        }
    }

    fn overwrite(&mut self, image: u64, how: &str, full: bool) {
        let keys: Vec<ImageKey> = self.images.keys().filter(|k| k.image == image).copied().collect();
        for key in keys {
            if full {
                self.replaced(key, &format!("overwritten by {how}"));
            }
            if let Some(state) = self.images.get_mut(&key) {
                state.discarded = None;
            }
        }
    }

    /// New contents replace all of `key`: stored contents nobody read were stored for nothing.
    fn replaced(&mut self, key: ImageKey, by: &str) {
        let Some(o) = self.images.get_mut(&key).and_then(|s| s.unread.take()) else { return };
        let detail =
            format!("{} stored by {}, then {by} before anything read it", o.attachment, pass_name(o.pass, &o.label));
        self.flag("stored_then_overwritten", (o.frame, o.pass, &o.label), Some(&o.attachment), detail);
        self.output_unread(o.record);
    }

    fn outside_pass(&mut self, image: u64, transient: bool, how: &str) {
        if !transient {
            return;
        }
        // Named by the pass that last used it as an attachment, when there was one.
        let last = self
            .images
            .iter()
            .filter(|(k, _)| k.image == image)
            .find_map(|(_, s)| s.unread.clone().or_else(|| s.discarded.clone()));
        let (origin, attachment) = match &last {
            Some(o) => ((o.frame, o.pass, &o.label), Some(o.attachment.as_str())),
            None => ((self.frame, self.position, &None), None),
        };
        let what = attachment.unwrap_or("an image");
        let detail = format!(
            "{what} has TRANSIENT_ATTACHMENT usage (it may live in tile memory only) and is used outside its pass by {how}"
        );
        let (frame, pass, label) = (origin.0, origin.1, origin.2.clone());
        let attachment = attachment.map(str::to_owned);
        self.flag("transient_outside_pass", (frame, pass, &label), attachment.as_deref(), detail);
    }

    /// One stored output of pass `record` was never read: when none of its outputs was, the
    /// pass was dead.
    fn output_unread(&mut self, record: usize) {
        let Some(r) = self.passes.get_mut(&record) else { return };
        r.pending = r.pending.saturating_sub(1);
        if r.pending > 0 {
            return;
        }
        let Some(r) = self.passes.remove(&record) else { return };
        if !r.read_any {
            let (frame, pass, label) = (r.frame, r.pass, r.label);
            let detail = format!(
                "{} stores outputs that nothing reads before the frame ends: the pass is dead",
                pass_name(pass, &label)
            );
            self.flag("dead_pass", (frame, pass, &label), None, detail);
        }
    }

    fn never_read(&mut self, older_than: u64) {
        let keys: Vec<ImageKey> = self
            .images
            .iter()
            .filter(|(_, s)| s.unread.as_ref().is_some_and(|o| o.frame < older_than))
            .map(|(k, _)| *k)
            .collect();
        for key in keys {
            let Some(o) = self.images.get_mut(&key).and_then(|s| s.unread.take()) else { continue };
            let detail = format!(
                "{} is stored by {} and nothing reads it: store DONT_CARE (and make it transient)",
                o.attachment,
                pass_name(o.pass, &o.label)
            );
            self.flag("stored_never_read", (o.frame, o.pass, &o.label), Some(&o.attachment), detail);
            self.output_unread(o.record);
        }
    }

    /// A present ends the frame: outputs stored in an earlier frame and still unread are
    /// never read (one frame's grace for history buffers).
    pub fn end_frame(&mut self) {
        self.never_read(self.frame);
        self.frame += 1;
        self.position = 0;
    }

    /// A GL or GLES program's buffer swap ends the frame (`profile-app --gl`). zink shows the
    /// swapped image by reading it on the host, which the layer does not see: the colour
    /// attachments the frame's last pass stored are taken as that image, and read.
    pub fn swapped(&mut self) {
        for key in std::mem::take(&mut self.last_colours) {
            self.read_key(key);
        }
        self.end_frame();
    }

    /// The device is destroyed: every output still unread was never read.
    pub fn finish(&mut self) {
        self.never_read(u64::MAX);
    }
}

#[cfg(test)]
mod tests;
