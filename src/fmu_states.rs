//! FMU states (`fmi2FMUstate`): snapshots of an instance's [`InstanceValues`] handed to the host
//! as opaque pointers, and their serialized form: a header line, the GUID line, then JSON.

use std::ffi::c_void;

use mf87::InputVar;
use mf87::bounds::SPEED_MPS;
use mf87::extensions::LAGGED_SLIP_ABS_MAX;

use crate::instance_values::InstanceValues;
use crate::variables::GUID;

/// Serialized FMU states start with this header, followed by JSON.
const SERIAL_HEADER: &[u8] = b"Pacejka87Tire FMU state v2\n";
/// Why an `fmi2FMUstate` argument was refused.
pub(crate) const NOT_A_STATE: &str =
    "FMUstate is NULL, not a state of this instance, or was freed already";

/// A copy of the FMU state, handed to the host as an opaque `fmi2FMUstate`.
pub(crate) struct Snapshot {
    model: InstanceValues,
}

impl Snapshot {
    pub(crate) fn model(&self) -> &InstanceValues {
        &self.model
    }
}

/// The FMU states of one instance: every pointer it handed out and has not freed. A pointer
/// is dereferenced only if it is in this list, so a state of another instance, one freed
/// already or a garbage pointer is refused without being read (an address the allocator
/// reuses for a new state of this instance is that new state). Dropping the list (with the
/// instance, fmi2FreeInstance) frees the states the host did not free.
#[derive(Default)]
pub(crate) struct Snapshots {
    live: Vec<*mut Snapshot>,
}

impl Snapshots {
    /// The state behind a host pointer, if it is a live state of this instance.
    pub(crate) fn get(&self, ptr: *mut c_void) -> Option<&Snapshot> {
        let ptr = ptr as *mut Snapshot;
        self.live.contains(&ptr).then(|| {
            // SAFETY: every pointer in `live` came from Box::into_raw and is freed only when
            // it leaves the list.
            unsafe { &*ptr }
        })
    }

    /// Puts `model` into `*slot`: into the state already there if any, else a new one.
    /// A slot holding anything but NULL or a live state of this instance is refused with
    /// [`NOT_A_STATE`].
    pub(crate) fn store(
        &mut self,
        slot: &mut *mut c_void,
        model: InstanceValues,
    ) -> Result<(), &'static str> {
        if slot.is_null() {
            let ptr = Box::into_raw(Box::new(Snapshot { model }));
            self.live.push(ptr);
            *slot = ptr as *mut c_void;
            return Ok(());
        }
        let ptr = *slot as *mut Snapshot;
        if !self.live.contains(&ptr) {
            return Err(NOT_A_STATE);
        }
        // SAFETY: live, see `get`; no other reference to it exists during this call.
        unsafe { (*ptr).model = model };
        Ok(())
    }

    /// Frees the state `ptr`; false if it is not a live state of this instance.
    pub(crate) fn free(&mut self, ptr: *mut c_void) -> bool {
        let ptr = ptr as *mut Snapshot;
        match self.live.iter().position(|p| *p == ptr) {
            Some(i) => {
                self.live.swap_remove(i);
                // SAFETY: from Box::into_raw in `store`, removed from `live`: freed once.
                drop(unsafe { Box::from_raw(ptr) });
                true
            }
            None => false,
        }
    }

    /// How many states are allocated.
    pub(crate) fn len(&self) -> usize {
        self.live.len()
    }
}

impl Drop for Snapshots {
    fn drop(&mut self) {
        for ptr in self.live.drain(..) {
            // SAFETY: as in `free`.
            drop(unsafe { Box::from_raw(ptr) });
        }
    }
}

/// The serialized form of `model`.
pub(crate) fn serialize(model: &InstanceValues) -> serde_json::Result<Vec<u8>> {
    let mut bytes = SERIAL_HEADER.to_vec();
    bytes.extend(GUID.as_bytes());
    bytes.push(b'\n');
    serde_json::to_writer(&mut bytes, model)?;
    Ok(bytes)
}

/// The state serialized in `bytes`, if this FMU (header, GUID) wrote it and its parameters
/// and values are valid.
pub(crate) fn deserialize(bytes: &[u8]) -> Result<InstanceValues, String> {
    let rest = bytes
        .strip_prefix(SERIAL_HEADER)
        .ok_or("wrong header or version")?;
    let rest = rest
        .strip_prefix(GUID.as_bytes())
        .and_then(|r| r.strip_prefix(b"\n"))
        .ok_or("made by an FMU with another GUID")?;
    let model: InstanceValues = serde_json::from_slice(rest).map_err(|e| e.to_string())?;
    model.params.validate().map_err(|e| e.to_string())?;
    let l = &model.lagged;
    if ![l.fx, l.fy, l.mz]
        .iter()
        .all(|x| x.abs() <= LAGGED_SLIP_ABS_MAX)
    {
        return Err(format!(
            "relaxation states {:?} beyond +-{LAGGED_SLIP_ABS_MAX}",
            [l.fx, l.fy, l.mz]
        ));
    }
    if !SPEED_MPS.contains(model.conditions.vx.abs()) {
        return Err(format!(
            "vx = {} m/s: |vx| must lie in {SPEED_MPS} m/s",
            model.conditions.vx
        ));
    }
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
