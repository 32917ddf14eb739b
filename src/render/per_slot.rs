//! Per-frame data kept a copy per frame slot (`Renderer::slot`): a frame writes and reads the
//! copy of the slot it is recorded in, made the first time that slot needs one, so that frames
//! in flight never share what the CPU rewrites.

use crate::error::Result;

/// Slot `slot`'s copy in `copies`, the missing ones up to it made by `make` first.
pub fn slot_copy<T>(copies: &mut Vec<T>, slot: usize, mut make: impl FnMut() -> Result<T>) -> Result<&mut T> {
    while copies.len() <= slot {
        copies.push(make()?);
    }
    Ok(&mut copies[slot])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slot_gets_its_copy_made_once_and_the_slots_before_it_too() {
        let mut copies = vec![10];
        let mut made = 0;
        *slot_copy(&mut copies, 2, || {
            made += 1;
            Ok(20)
        })
        .expect("made") += 1;
        assert_eq!((copies.as_slice(), made), (&[10, 20, 21][..], 2));
        assert_eq!(*slot_copy(&mut copies, 0, || unreachable!("slot 0 exists")).expect("kept"), 10);
        assert!(slot_copy(&mut copies, 4, || Err(crate::error::Error::Internal("no memory".into()))).is_err());
    }
}
