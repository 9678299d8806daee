//! The FMU state functions of an [`Instance`]: get, set and free a state, and its bytes
//! (the format and its checks are the model's snapshot, [`crate::model`]).

use super::*;

impl Instance {
    fn check_own(&self, snapshot: &Snapshot) -> Result<(), String> {
        if snapshot.guid == self.model.guid() {
            Ok(())
        } else {
            Err("FMUstate belongs to another FMU".to_string())
        }
    }

    /// Stores `snapshot` in `saved`: a new one, or over an existing state of this FMU.
    fn store(&self, saved: &mut Option<Snapshot>, snapshot: Snapshot) -> Result<(), String> {
        if let Some(existing) = saved {
            self.check_own(existing)?;
        }
        *saved = Some(snapshot);
        Ok(())
    }

    /// fmi2GetFMUstate: saves the state into `saved` (new, or overwriting a state of this FMU).
    pub fn get_fmu_state(&mut self, saved: &mut Option<Snapshot>) -> Status {
        self.run(Function::GetFmuState, |inst| {
            let snapshot = Snapshot {
                guid: inst.model.guid().to_string(),
                phase: inst.phase,
                state: inst.model.state().clone(),
            };
            inst.store(saved, snapshot)?;
            let text = format!("state saved at t = {}", inst.model.time());
            inst.log(Status::Ok, Category::Events, text);
            Ok(Status::Ok)
        })
    }

    /// fmi2SetFMUstate: restores a saved state, including its phase (this also leaves the
    /// error phase).
    pub fn set_fmu_state(&mut self, saved: &Snapshot) -> Status {
        self.run(Function::SetFmuState, |inst| {
            inst.check_own(saved)?;
            // The sea exists from the end of initialization on; in the error phase, as it is.
            let waves_started = match saved.phase {
                Phase::Instantiated | Phase::InitializationMode => false,
                Phase::StepComplete | Phase::Terminated => true,
                Phase::Error | Phase::Fatal => inst.model.waves_started(),
            };
            inst.model
                .set_state_and_waves(saved.state.clone(), waves_started)
                .map_err(|e| e.to_string())?;
            inst.phase = saved.phase;
            let text = format!("state restored at t = {}", inst.model.time());
            inst.log(Status::Ok, Category::Events, text);
            Ok(Status::Ok)
        })
    }

    /// Records the address of an FMU state the C layer issued for this instance.
    pub fn record_issued_state(&mut self, address: usize) {
        self.issued_states.insert(address);
    }

    /// Whether this instance issued the FMU state at `address` and has not freed it.
    pub fn issued_state(&self, address: usize) -> bool {
        self.issued_states.contains(&address)
    }

    /// Forgets a freed FMU state's address.
    pub fn forget_issued_state(&mut self, address: usize) {
        self.issued_states.remove(&address);
    }

    /// fmi2FreeFMUstate: drops a saved state (`None`: nothing to free).
    pub fn free_fmu_state(&mut self, saved: Option<Snapshot>) -> Status {
        self.run(Function::FreeFmuState, |_| {
            drop(saved);
            Ok(Status::Ok)
        })
    }

    /// fmi2SerializedFMUstateSize.
    pub fn serialized_fmu_state_size(&mut self, _saved: &Snapshot, size: &mut usize) -> Status {
        self.run(Function::SerializedFmuStateSize, |inst| {
            *size = inst.model.serialized_size();
            Ok(Status::Ok)
        })
    }

    /// fmi2SerializeFMUstate: `bytes` must have exactly the serialized size.
    pub fn serialize_fmu_state(&mut self, saved: &Snapshot, bytes: &mut [u8]) -> Status {
        self.run(Function::SerializeFmuState, |inst| {
            inst.check_own(saved)?;
            let serialized = inst.model.serialize_state(&saved.state, saved.phase.tag());
            if bytes.len() != serialized.len() {
                return Err(format!(
                    "size {}, the serialized state has {} bytes",
                    bytes.len(),
                    serialized.len()
                ));
            }
            bytes.copy_from_slice(&serialized);
            Ok(Status::Ok)
        })
    }

    /// fmi2DeSerializeFMUstate: reads serialized bytes into `saved` (new, or overwriting a
    /// state of this FMU); corrupt or foreign bytes are refused.
    pub fn deserialize_fmu_state(&mut self, bytes: &[u8], saved: &mut Option<Snapshot>) -> Status {
        self.run(Function::DeSerializeFmuState, |inst| {
            let (state, tag) = inst.model.deserialize(bytes).map_err(|e| e.to_string())?;
            let phase = Phase::from_tag(tag)
                .ok_or_else(|| format!("serialized phase {tag} is not valid"))?;
            let snapshot = Snapshot {
                guid: inst.model.guid().to_string(),
                phase,
                state,
            };
            inst.store(saved, snapshot)?;
            Ok(Status::Ok)
        })
    }
}
