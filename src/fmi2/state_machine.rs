//! The FMI 2.0 Co-Simulation calling-sequence state machine as a table (FMI 2.0.x, section
//! 4.2.4, "State Machine of Calling Sequence from Master to Slave"). Per-variable conditions
//! (which variables may be set or read in a state) are checked by the instance.

/// States of a Co-Simulation slave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum State {
    /// After fmi2Instantiate (and fmi2Reset).
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode,
    /// slaveInitialized / stepComplete.
    StepComplete,
    /// stepInProgress (never entered: no asynchronous steps).
    StepInProgress,
    /// After fmi2DoStep returned fmi2Discard.
    StepFailed,
    /// stepCanceled (never entered).
    StepCanceled,
    /// After fmi2Terminate.
    Terminated,
    /// After a call returned fmi2Error.
    Error,
    /// After a call returned fmi2Fatal.
    Fatal,
}

impl State {
    const fn bit(self) -> u16 {
        1 << (self as u16)
    }

    /// Name for messages.
    pub fn name(self) -> &'static str {
        match self {
            State::Instantiated => "Instantiated",
            State::InitializationMode => "Initialization Mode",
            State::StepComplete => "stepComplete",
            State::StepInProgress => "stepInProgress",
            State::StepFailed => "stepFailed",
            State::StepCanceled => "stepCanceled",
            State::Terminated => "Terminated",
            State::Error => "Error",
            State::Fatal => "Fatal",
        }
    }
}

/// FMI functions that act on an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Call {
    SetDebugLogging,
    FreeInstance,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetReal,
    GetInteger,
    GetBoolean,
    GetString,
    SetReal,
    SetInteger,
    SetBoolean,
    SetString,
    GetFmuState,
    SetFmuState,
    FreeFmuState,
    SerializedFmuStateSize,
    SerializeFmuState,
    DeSerializeFmuState,
    GetDirectionalDerivative,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
    GetRealStatus,
    GetIntegerStatus,
    GetBooleanStatus,
    GetStringStatus,
}

impl Call {
    /// The C function name.
    pub fn name(self) -> &'static str {
        match self {
            Call::SetDebugLogging => "fmi2SetDebugLogging",
            Call::FreeInstance => "fmi2FreeInstance",
            Call::SetupExperiment => "fmi2SetupExperiment",
            Call::EnterInitializationMode => "fmi2EnterInitializationMode",
            Call::ExitInitializationMode => "fmi2ExitInitializationMode",
            Call::Terminate => "fmi2Terminate",
            Call::Reset => "fmi2Reset",
            Call::GetReal => "fmi2GetReal",
            Call::GetInteger => "fmi2GetInteger",
            Call::GetBoolean => "fmi2GetBoolean",
            Call::GetString => "fmi2GetString",
            Call::SetReal => "fmi2SetReal",
            Call::SetInteger => "fmi2SetInteger",
            Call::SetBoolean => "fmi2SetBoolean",
            Call::SetString => "fmi2SetString",
            Call::GetFmuState => "fmi2GetFMUstate",
            Call::SetFmuState => "fmi2SetFMUstate",
            Call::FreeFmuState => "fmi2FreeFMUstate",
            Call::SerializedFmuStateSize => "fmi2SerializedFMUstateSize",
            Call::SerializeFmuState => "fmi2SerializeFMUstate",
            Call::DeSerializeFmuState => "fmi2DeSerializeFMUstate",
            Call::GetDirectionalDerivative => "fmi2GetDirectionalDerivative",
            Call::SetRealInputDerivatives => "fmi2SetRealInputDerivatives",
            Call::GetRealOutputDerivatives => "fmi2GetRealOutputDerivatives",
            Call::DoStep => "fmi2DoStep",
            Call::CancelStep => "fmi2CancelStep",
            Call::GetStatus => "fmi2GetStatus",
            Call::GetRealStatus => "fmi2GetRealStatus",
            Call::GetIntegerStatus => "fmi2GetIntegerStatus",
            Call::GetBooleanStatus => "fmi2GetBooleanStatus",
            Call::GetStringStatus => "fmi2GetStringStatus",
        }
    }

    /// States in which the call is allowed (conditions 1–8 of the standard's table count as
    /// allowed here; the instance checks them per variable).
    const fn mask(self) -> u16 {
        use State::*;
        const INST: u16 = Instantiated.bit();
        const INIT: u16 = InitializationMode.bit();
        const DONE: u16 = StepComplete.bit();
        const PROG: u16 = StepInProgress.bit();
        const FAIL: u16 = StepFailed.bit();
        const CANC: u16 = StepCanceled.bit();
        const TERM: u16 = Terminated.bit();
        const ERR: u16 = Error.bit();
        match self {
            Call::SetDebugLogging => INST | INIT | DONE | PROG | FAIL | CANC | TERM | ERR,
            Call::FreeInstance => INST | INIT | DONE | FAIL | CANC | TERM | ERR,
            Call::SetupExperiment => INST,
            Call::EnterInitializationMode => INST,
            Call::ExitInitializationMode => INIT,
            Call::Terminate => DONE | FAIL,
            Call::Reset => INST | INIT | DONE | FAIL | CANC | TERM | ERR,
            Call::GetReal | Call::GetInteger | Call::GetBoolean | Call::GetString => {
                INIT | DONE | FAIL | CANC | TERM | ERR
            }
            // Inputs may also be set in Instantiated (importers such as fmpy do), see
            // `Instance::set`.
            Call::SetReal | Call::SetInteger | Call::SetBoolean | Call::SetString => {
                INST | INIT | DONE
            }
            Call::GetFmuState => INST | INIT | DONE | FAIL | CANC | TERM | ERR,
            Call::SetFmuState
            | Call::FreeFmuState
            | Call::SerializedFmuStateSize
            | Call::SerializeFmuState
            | Call::DeSerializeFmuState => INST | INIT | DONE | FAIL | CANC | TERM | ERR,
            Call::GetDirectionalDerivative => INIT | DONE | FAIL | CANC | TERM | ERR,
            Call::SetRealInputDerivatives => INST | INIT | DONE,
            Call::GetRealOutputDerivatives => DONE | FAIL | CANC | TERM | ERR,
            Call::DoStep => DONE,
            Call::CancelStep => PROG,
            Call::GetStatus
            | Call::GetRealStatus
            | Call::GetIntegerStatus
            | Call::GetBooleanStatus
            | Call::GetStringStatus => DONE | PROG | FAIL | TERM,
        }
    }

    /// Whether the call is allowed in `state`.
    pub fn allowed_in(self, state: State) -> bool {
        self.mask() & state.bit() != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_spot_checks() {
        assert!(Call::DoStep.allowed_in(State::StepComplete));
        assert!(!Call::DoStep.allowed_in(State::InitializationMode));
        assert!(!Call::DoStep.allowed_in(State::StepFailed));
        assert!(Call::Terminate.allowed_in(State::StepFailed));
        assert!(!Call::Terminate.allowed_in(State::Instantiated));
        assert!(Call::FreeInstance.allowed_in(State::Error));
        assert!(!Call::SetReal.allowed_in(State::Terminated));
        assert!(Call::GetBooleanStatus.allowed_in(State::StepFailed));
        assert!(!Call::ExitInitializationMode.allowed_in(State::Instantiated));
        assert!(!Call::SetDebugLogging.allowed_in(State::Fatal));
    }
}
