//! FMU states (fmi2GetFMUstate & co.) and their byte serialization.
//!
//! An `fmi2FMUstate` is a `Box<Snapshot<M>>`: a clone of the model plus the
//! plumbing state (state-machine state, time, stop time), so restoring it is
//! bit-identical. Logger settings are not part of it.
//!
//! Serialized layout (all integers little-endian), format version 1:
//!
//! | bytes | content |
//! |-------|---------|
//! | 8     | the model's magic bytes ([`FmuModel::STATE_MAGIC`]) |
//! | 4     | format version (u32) |
//! | 4 + n | GUID of the model description: length (u32), UTF-8 bytes |
//! | 1     | state-machine state (`Mode` as u8) |
//! | 8     | time (f64) |
//! | 1 + 8 | stop time defined (u8 0/1), stop time (f64) |
//! | 8 + m | model bytes from `FmuModel::serialize`: length (u64), bytes |
//! | 8     | FNV-1a 64 checksum of everything before it |
//!
//! Deserialization checks magic, version, bounds (truncation), GUID and
//! checksum, and never reads past the end of the buffer.

use std::collections::HashSet;
use std::ffi::c_void;
use std::marker::PhantomData;

use super::instance::{Mode, Plumbing};
use super::model::FmuModel;

/// Version of the serialized layout above.
pub const FORMAT_VERSION: u32 = 1;

/// Marks a live `Snapshot` in memory (a second line of defence behind
/// [`Registry`]; cleared when the state is freed).
const LIVE_TAG: u64 = 0x464d_5553_5441_5445; // "FMUSTATE"

/// What an `fmi2FMUstate` points to.
#[derive(Clone)]
pub struct Snapshot<M> {
    tag: u64,
    /// The plumbing's state at the time of the snapshot.
    pub plumbing: Plumbing,
    /// A clone of the model.
    pub model: M,
}

impl<M: FmuModel> Snapshot<M> {
    /// A live snapshot.
    pub fn new(plumbing: Plumbing, model: M) -> Self {
        Snapshot {
            tag: LIVE_TAG,
            plumbing,
            model,
        }
    }

    /// Whether the snapshot has not been freed.
    pub fn is_live(&self) -> bool {
        self.tag == LIVE_TAG
    }

    /// Clear the tag before the memory is freed (helps to detect a
    /// double free or use after free; best effort).
    pub fn kill(&mut self) {
        self.tag = 0;
    }

    /// The serialized bytes (layout in the module documentation).
    pub fn serialize(&self) -> Vec<u8> {
        let mut model = Vec::new();
        self.model.serialize(&mut model);

        let guid = M::description().guid;
        let mut out = Vec::with_capacity(64 + guid.len() + model.len());
        out.extend_from_slice(&M::STATE_MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&(guid.len() as u32).to_le_bytes());
        out.extend_from_slice(guid.as_bytes());
        out.push(self.plumbing.mode as u8);
        out.extend_from_slice(&self.plumbing.time.to_le_bytes());
        out.push(u8::from(self.plumbing.stop_time.is_some()));
        out.extend_from_slice(&self.plumbing.stop_time.unwrap_or(0.0).to_le_bytes());
        out.extend_from_slice(&(model.len() as u64).to_le_bytes());
        out.extend_from_slice(&model);
        let checksum = fnv1a_64(&out);
        out.extend_from_slice(&checksum.to_le_bytes());
        out
    }

    /// A snapshot from [`Snapshot::serialize`] bytes; `Err` says what is wrong with them.
    pub fn deserialize(bytes: &[u8]) -> Result<Self, String> {
        let mut r = Reader { bytes, pos: 0 };
        let description = M::description();
        if r.take(M::STATE_MAGIC.len(), "magic")? != M::STATE_MAGIC {
            return Err(format!(
                "not a serialized {} FMU state (bad magic bytes)",
                description.model_identifier
            ));
        }
        let version = r.u32("format version")?;
        if version != FORMAT_VERSION {
            return Err(format!(
                "serialized FMU state has format version {version}; this FMU reads version {FORMAT_VERSION}"
            ));
        }
        let guid_len = r.u32("GUID length")? as usize;
        let guid = r.take(guid_len, "GUID")?;
        if guid != description.guid.as_bytes() {
            return Err(format!(
                "serialized FMU state belongs to the model description with GUID {}, this FMU has GUID {}",
                String::from_utf8_lossy(guid),
                description.guid
            ));
        }
        let mode_byte = r.u8("state")?;
        let mode = Mode::from_u8(mode_byte)
            .ok_or_else(|| format!("invalid state-machine state {mode_byte}"))?;
        let time = r.f64("time")?;
        let stop_defined = r.u8("stop-time flag")?;
        let stop = r.f64("stop time")?;
        let stop_time = match stop_defined {
            0 => None,
            1 => Some(stop),
            x => return Err(format!("invalid stop-time flag {x}")),
        };
        let model_len =
            usize::try_from(r.u64("model length")?).map_err(|_| "model length overflows")?;
        let model_bytes = r.take(model_len, "model data")?;
        let body_len = r.pos;
        let checksum = r.u64("checksum")?;
        if r.pos != bytes.len() {
            return Err(format!(
                "{} unexpected bytes after the checksum",
                bytes.len() - r.pos
            ));
        }
        if checksum != fnv1a_64(&bytes[..body_len]) {
            return Err("serialized FMU state is corrupted (checksum mismatch)".into());
        }
        if !time.is_finite() || stop_time.is_some_and(|s| !s.is_finite()) {
            return Err("serialized FMU state has a non-finite time".into());
        }
        let model = M::deserialize(model_bytes).map_err(|e| format!("model data: {e}"))?;
        Ok(Snapshot::new(
            Plumbing {
                mode,
                time,
                stop_time,
            },
            model,
        ))
    }
}

/// The FMU states one instance has handed out and not yet freed (FMI 2.0
/// section 2.1.8: a state belongs to the instance that made it).
///
/// An `fmi2FMUstate` from the importer is looked up here *before* it is
/// dereferenced, so a pointer this instance never handed out (another
/// instance's state, an uninitialised variable, a state freed already) is
/// refused with fmi2Error instead of being read. fmi2FreeInstance frees
/// the states the importer left (the standard: it "frees all the allocated
/// memory ... allocated by the functions of the FMU interface").
pub struct Registry<M> {
    live: HashSet<usize>,
    _model: PhantomData<M>,
}

impl<M> Default for Registry<M> {
    fn default() -> Self {
        Registry {
            live: HashSet::new(),
            _model: PhantomData,
        }
    }
}

impl<M: FmuModel> Registry<M> {
    /// A new heap state, registered; the pointer goes to the importer.
    pub fn insert(&mut self, snap: Snapshot<M>) -> *mut Snapshot<M> {
        let p = Box::into_raw(Box::new(snap));
        self.live.insert(p as usize);
        p
    }

    /// The live state behind `p`, if this instance handed it out.
    pub fn get(&mut self, p: *mut c_void, what: &str) -> Result<&mut Snapshot<M>, String> {
        if p.is_null() {
            return Err(format!("{what} is a NULL pointer"));
        }
        if !self.live.contains(&(p as usize)) {
            return Err(format!(
                "{what} = {p:p} is not a live FMU state of this instance (freed already, from another instance, or never set)"
            ));
        }
        // SAFETY: registered by `insert` (a live Box of this type) and not
        // yet freed; `&mut self` makes the access exclusive.
        Ok(unsafe { &mut *(p as *mut Snapshot<M>) })
    }

    /// Free the state behind `p` (which `get` accepts).
    pub fn free(&mut self, p: *mut c_void, what: &str) -> Result<(), String> {
        self.get(p, what)?.kill();
        self.live.remove(&(p as usize));
        // SAFETY: allocated by `insert` with Box::into_raw and removed from
        // the registry above, so freed exactly once.
        drop(unsafe { Box::from_raw(p as *mut Snapshot<M>) });
        Ok(())
    }

    /// Number of live states.
    pub fn len(&self) -> usize {
        self.live.len()
    }

    /// Whether no state is live.
    pub fn is_empty(&self) -> bool {
        self.live.is_empty()
    }
}

impl<M> Drop for Registry<M> {
    fn drop(&mut self) {
        for p in self.live.drain() {
            // SAFETY: every registered pointer is a live Box<Snapshot<M>>.
            drop(unsafe { Box::from_raw(p as *mut Snapshot<M>) });
        }
    }
}

/// 64-bit FNV-1a.
pub fn fnv1a_64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Bounds-checked little-endian reader.
struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len()).ok_or_else(|| {
            format!(
                "serialized FMU state is truncated: {what} needs {n} bytes at offset {}, only {} left",
                self.pos,
                self.bytes.len() - self.pos
            )
        })?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        let mut a = [0; N];
        a.copy_from_slice(self.take(N, what)?);
        Ok(a)
    }

    fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.array::<1>(what)?[0])
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }

    fn f64(&mut self, what: &str) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }
}

#[cfg(test)]
mod tests {
    use super::fnv1a_64;

    #[test]
    fn fnv1a_64_known_values() {
        assert_eq!(fnv1a_64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a_64(b"a"), 0xaf63dc4c8601ec8c);
    }
}
