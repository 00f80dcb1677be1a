//! FMU states (`fmi2FMUstate`): snapshots of an instance's [`ModelState`] handed to the host
//! as opaque pointers, and their serialized form: a header line, the GUID line, then JSON.

use std::ffi::c_void;

use mf87::InputVar;

use crate::model_state::ModelState;
use crate::variables::GUID;

/// First field of every FMU state snapshot; cleared on free.
const SNAPSHOT_MAGIC: u64 = 0x5041_4338_3753_4e50; // "PAC87SNP"
/// Serialized FMU states start with this header, followed by JSON.
const SERIAL_HEADER: &[u8] = b"Pacejka87Tire FMU state v2\n";
/// Why an `fmi2FMUstate` argument was refused.
pub(crate) const NOT_A_STATE: &str = "FMUstate is NULL, not a state of this FMU, or was freed";

/// A copy of the FMU state, handed to the host as an opaque `fmi2FMUstate`.
#[repr(C)]
pub(crate) struct Snapshot {
    magic: u64,
    model: ModelState,
}

impl Snapshot {
    /// The snapshot behind a host pointer, if it is one of ours and still alive.
    ///
    /// # Safety
    /// `ptr` must be NULL or a pointer obtained from fmi2GetFMUstate / fmi2DeSerializeFMUstate.
    pub(crate) unsafe fn from_ptr<'a>(ptr: *mut c_void) -> Option<&'a mut Snapshot> {
        let snapshot = ptr as *mut Snapshot;
        // SAFETY: non-NULL pointers are, by contract, snapshots we allocated (the magic
        // guards against ones already freed while their memory is still mapped).
        unsafe { snapshot.as_mut() }.filter(|s| s.magic == SNAPSHOT_MAGIC)
    }

    /// Frees a snapshot made by [`Snapshot::store`].
    ///
    /// # Safety
    /// As [`Snapshot::from_ptr`]; the pointer must not be used afterwards.
    pub(crate) unsafe fn free(ptr: *mut c_void) -> bool {
        // SAFETY: forwarded.
        match unsafe { Self::from_ptr(ptr) } {
            Some(s) => {
                s.magic = 0;
                // SAFETY: allocated by Box::into_raw in `into_ptr`.
                drop(unsafe { Box::from_raw(s as *mut Snapshot) });
                true
            }
            None => false,
        }
    }

    /// Puts `model` into `*slot`: into the snapshot already there if any, else a new one.
    /// A slot holding anything but NULL or a live snapshot is refused with [`NOT_A_STATE`].
    pub(crate) fn store(slot: &mut *mut c_void, model: ModelState) -> Result<(), &'static str> {
        if slot.is_null() {
            *slot = Snapshot::into_ptr(model);
            return Ok(());
        }
        // SAFETY: the host hands back a pointer from an earlier get/deserialize.
        match unsafe { Snapshot::from_ptr(*slot) } {
            Some(s) => {
                s.model = model;
                Ok(())
            }
            None => Err(NOT_A_STATE),
        }
    }

    pub(crate) fn model(&self) -> &ModelState {
        &self.model
    }

    fn into_ptr(model: ModelState) -> *mut c_void {
        Box::into_raw(Box::new(Snapshot {
            magic: SNAPSHOT_MAGIC,
            model,
        })) as *mut c_void
    }
}

/// The serialized form of `model`.
pub(crate) fn serialize(model: &ModelState) -> serde_json::Result<Vec<u8>> {
    let mut bytes = SERIAL_HEADER.to_vec();
    bytes.extend(GUID.as_bytes());
    bytes.push(b'\n');
    serde_json::to_writer(&mut bytes, model)?;
    Ok(bytes)
}

/// The state serialized in `bytes`, if this FMU (header, GUID) wrote it and its parameters
/// and values are valid.
pub(crate) fn deserialize(bytes: &[u8]) -> Result<ModelState, String> {
    let rest = bytes
        .strip_prefix(SERIAL_HEADER)
        .ok_or("wrong header or version")?;
    let rest = rest
        .strip_prefix(GUID.as_bytes())
        .and_then(|r| r.strip_prefix(b"\n"))
        .ok_or("made by an FMU with another GUID")?;
    let model: ModelState = serde_json::from_slice(rest).map_err(|e| e.to_string())?;
    model.params.validate().map_err(|e| e.to_string())?;
    let (o, c, l) = (&model.outputs, &model.conditions, &model.lagged);
    let finite = InputVar::ALL
        .iter()
        .all(|v| model.inputs.get(*v).is_finite())
        && model.time.is_finite()
        && [o.fx, o.fy, o.mz, c.vx, c.p, c.t_tread, l.fx, l.fy, l.mz]
            .iter()
            .all(|x| x.is_finite());
    if !finite {
        return Err("non-finite values".into());
    }
    Ok(model)
}
