//! The phases of an instance and the one table of the phases each FMI function is allowed
//! in, written to be read next to the FMI 2.0 co-simulation state table (section 4.2.4).

/// Phase of an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Phase {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated = 0,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode = 1,
    /// Initialized; ready for fmi2DoStep.
    StepComplete = 2,
    /// After fmi2Terminate.
    Terminated = 3,
    /// After a failed call; fmi2Reset or fmi2SetFMUstate recover.
    Error = 4,
    /// After a caught panic; only fmi2FreeInstance.
    Fatal = 5,
}

impl Phase {
    /// The phase a saved state was in (`None` for an unknown tag or Fatal, never saved).
    pub fn from_tag(tag: u8) -> Option<Phase> {
        Some(match tag {
            0 => Phase::Instantiated,
            1 => Phase::InitializationMode,
            2 => Phase::StepComplete,
            3 => Phase::Terminated,
            4 => Phase::Error,
            _ => return None,
        })
    }

    /// The tag stored in a serialized state.
    pub fn tag(self) -> u8 {
        self as u8
    }
}

/// A set of phases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PhaseSet(u8);

impl PhaseSet {
    /// From one row of [`allowed`]: one cell per phase, in the order of [`Phase`].
    const fn row(cells: [bool; 6]) -> PhaseSet {
        let mut bits = 0;
        let mut i = 0;
        while i < cells.len() {
            if cells[i] {
                bits |= 1 << i;
            }
            i += 1;
        }
        PhaseSet(bits)
    }

    /// Whether the set holds `phase`.
    pub fn contains(self, phase: Phase) -> bool {
        self.0 & (1 << phase as u8) != 0
    }
}

/// An FMI function that works on an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    /// `fmi2SetDebugLogging`.
    SetDebugLogging,
    /// `fmi2SetupExperiment`.
    SetupExperiment,
    /// `fmi2EnterInitializationMode`.
    EnterInitializationMode,
    /// `fmi2ExitInitializationMode`.
    ExitInitializationMode,
    /// `fmi2Terminate`.
    Terminate,
    /// `fmi2Reset`.
    Reset,
    /// `fmi2GetReal`.
    GetReal,
    /// `fmi2GetInteger`.
    GetInteger,
    /// `fmi2GetBoolean`.
    GetBoolean,
    /// `fmi2GetString`.
    GetString,
    /// `fmi2SetReal`.
    SetReal,
    /// `fmi2SetInteger`.
    SetInteger,
    /// `fmi2SetBoolean`.
    SetBoolean,
    /// `fmi2SetString`.
    SetString,
    /// `fmi2GetFMUstate`.
    GetFmuState,
    /// `fmi2SetFMUstate`.
    SetFmuState,
    /// `fmi2FreeFMUstate`.
    FreeFmuState,
    /// `fmi2SerializedFMUstateSize`.
    SerializedFmuStateSize,
    /// `fmi2SerializeFMUstate`.
    SerializeFmuState,
    /// `fmi2DeSerializeFMUstate`.
    DeSerializeFmuState,
    /// `fmi2GetDirectionalDerivative`.
    GetDirectionalDerivative,
    /// `fmi2SetRealInputDerivatives`.
    SetRealInputDerivatives,
    /// `fmi2GetRealOutputDerivatives`.
    GetRealOutputDerivatives,
    /// `fmi2DoStep`.
    DoStep,
    /// `fmi2CancelStep`.
    CancelStep,
    /// `fmi2GetStatus`.
    GetStatus,
    /// `fmi2GetRealStatus`.
    GetRealStatus,
    /// `fmi2GetIntegerStatus`.
    GetIntegerStatus,
    /// `fmi2GetBooleanStatus`.
    GetBooleanStatus,
    /// `fmi2GetStringStatus`.
    GetStringStatus,
}

impl Function {
    /// Every function, in the order of the FMI 2.0 state table.
    pub const ALL: [Function; 30] = {
        use Function::*;
        [
            SetDebugLogging,
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
        ]
    };

    /// The C name in `standard`: the FMI 3.0 function that does this function's work (for
    /// fmi2SetupExperiment, fmi3EnterInitializationMode, which takes its arguments).
    pub fn name_in(self, standard: Standard) -> &'static str {
        use Function::*;
        match (standard, self) {
            (Standard::Fmi2, _) => self.name(),
            (Standard::Fmi3, SetupExperiment | EnterInitializationMode) => {
                "fmi3EnterInitializationMode"
            }
            (Standard::Fmi3, GetReal) => "fmi3GetFloat64",
            (Standard::Fmi3, GetInteger) => "fmi3GetInt32",
            (Standard::Fmi3, SetReal) => "fmi3SetFloat64",
            (Standard::Fmi3, SetInteger) => "fmi3SetInt32",
            (Standard::Fmi3, GetFmuState) => "fmi3GetFMUState",
            (Standard::Fmi3, SetFmuState) => "fmi3SetFMUState",
            (Standard::Fmi3, FreeFmuState) => "fmi3FreeFMUState",
            (Standard::Fmi3, SerializedFmuStateSize) => "fmi3SerializedFMUStateSize",
            (Standard::Fmi3, SerializeFmuState) => "fmi3SerializeFMUState",
            (Standard::Fmi3, DeSerializeFmuState) => "fmi3DeserializeFMUState",
            (Standard::Fmi3, GetRealOutputDerivatives) => "fmi3GetOutputDerivatives",
            // The rest keep their FMI 2.0 name with the prefix changed.
            (Standard::Fmi3, f) => FMI3_SAME_NAMES
                .iter()
                .find(|(g, _)| *g == f)
                .map_or("fmi3 (no equivalent)", |(_, n)| n),
        }
    }

    /// The FMI 2.0 C name.
    pub fn name(self) -> &'static str {
        use Function::*;
        match self {
            SetDebugLogging => "fmi2SetDebugLogging",
            SetupExperiment => "fmi2SetupExperiment",
            EnterInitializationMode => "fmi2EnterInitializationMode",
            ExitInitializationMode => "fmi2ExitInitializationMode",
            Terminate => "fmi2Terminate",
            Reset => "fmi2Reset",
            GetReal => "fmi2GetReal",
            GetInteger => "fmi2GetInteger",
            GetBoolean => "fmi2GetBoolean",
            GetString => "fmi2GetString",
            SetReal => "fmi2SetReal",
            SetInteger => "fmi2SetInteger",
            SetBoolean => "fmi2SetBoolean",
            SetString => "fmi2SetString",
            GetFmuState => "fmi2GetFMUstate",
            SetFmuState => "fmi2SetFMUstate",
            FreeFmuState => "fmi2FreeFMUstate",
            SerializedFmuStateSize => "fmi2SerializedFMUstateSize",
            SerializeFmuState => "fmi2SerializeFMUstate",
            DeSerializeFmuState => "fmi2DeSerializeFMUstate",
            GetDirectionalDerivative => "fmi2GetDirectionalDerivative",
            SetRealInputDerivatives => "fmi2SetRealInputDerivatives",
            GetRealOutputDerivatives => "fmi2GetRealOutputDerivatives",
            DoStep => "fmi2DoStep",
            CancelStep => "fmi2CancelStep",
            GetStatus => "fmi2GetStatus",
            GetRealStatus => "fmi2GetRealStatus",
            GetIntegerStatus => "fmi2GetIntegerStatus",
            GetBooleanStatus => "fmi2GetBooleanStatus",
            GetStringStatus => "fmi2GetStringStatus",
        }
    }
}

/// The functions FMI 3.0 keeps under the same name (prefix fmi3).
const FMI3_SAME_NAMES: [(Function, &str); 10] = [
    (Function::SetDebugLogging, "fmi3SetDebugLogging"),
    (
        Function::ExitInitializationMode,
        "fmi3ExitInitializationMode",
    ),
    (Function::Terminate, "fmi3Terminate"),
    (Function::Reset, "fmi3Reset"),
    (Function::GetBoolean, "fmi3GetBoolean"),
    (Function::GetString, "fmi3GetString"),
    (Function::SetBoolean, "fmi3SetBoolean"),
    (Function::SetString, "fmi3SetString"),
    (Function::DoStep, "fmi3DoStep"),
    (
        Function::GetDirectionalDerivative,
        "fmi3GetDirectionalDerivative",
    ),
];

/// The standard an instance was made through: it names the functions in log messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standard {
    /// FMI 2.0 (`fmi2Instantiate`).
    Fmi2,
    /// FMI 3.0 (`fmi3InstantiateCoSimulation`); the phase "stepComplete" is FMI 3.0's
    /// "Step Mode".
    Fmi3,
}

/// Allowed.
const X: bool = true;
/// Not allowed.
const __: bool = false;

/// The phases `function` may be called in: the FMI 2.0 co-simulation table "State Machine
/// of Calling Sequence from Master to Slave" (section 4.2.4), one row per function.
///
/// The columns are the standard's "instantiated", "initialization mode", "stepComplete",
/// "terminated", "error" and "fatal". Its other columns do not occur here: "start, end"
/// (fmi2GetTypesPlatform, fmi2GetVersion and fmi2Instantiate need no instance;
/// fmi2FreeInstance is allowed in every phase) and "stepInProgress", "stepFailed",
/// "stepCanceled" (fmi2DoStep is synchronous and never returns fmi2Pending or fmi2Discard).
/// A call outside its row is refused with fmi2Error and the phase stays.
#[rustfmt::skip]
pub const fn allowed(function: Function) -> PhaseSet {
    use Function::*;
    PhaseSet::row(match function {
        //                             instantiated
        //                             |   initialization mode
        //                             |   |   stepComplete
        //                             |   |   |   terminated
        //                             |   |   |   |   error
        //                             |   |   |   |   |   fatal
        SetDebugLogging =>            [X , X , X , X , X , __],
        SetupExperiment =>            [X , __, __, __, __, __],
        EnterInitializationMode =>    [X , __, __, __, __, __],
        ExitInitializationMode =>     [__, X , __, __, __, __],
        Terminate =>                  [__, __, X , __, __, __],
        Reset =>                      [X , X , X , X , X , __],
        GetReal =>                    [__, X , X , X , X , __],
        GetInteger =>                 [__, X , X , X , X , __],
        GetBoolean =>                 [__, X , X , X , X , __],
        GetString =>                  [__, X , X , X , X , __],
        SetReal =>                    [X , X , X , __, __, __],
        SetInteger =>                 [X , X , X , __, __, __],
        SetBoolean =>                 [X , X , X , __, __, __],
        SetString =>                  [X , X , X , __, __, __],
        GetFmuState =>                [X , X , X , X , X , __],
        SetFmuState =>                [X , X , X , X , X , __],
        FreeFmuState =>               [X , X , X , X , X , __],
        SerializedFmuStateSize =>     [X , X , X , X , X , __],
        SerializeFmuState =>          [X , X , X , X , X , __],
        DeSerializeFmuState =>        [X , X , X , X , X , __],
        GetDirectionalDerivative =>   [__, X , X , X , X , __],
        SetRealInputDerivatives =>    [X , X , X , __, __, __],
        GetRealOutputDerivatives =>   [__, __, X , X , X , __],
        DoStep =>                     [__, __, X , __, __, __],
        CancelStep =>                 [__, __, __, __, __, __],
        GetStatus =>                  [__, __, X , X , __, __],
        GetRealStatus =>              [__, __, X , X , __, __],
        GetIntegerStatus =>           [__, __, X , X , __, __],
        GetBooleanStatus =>           [__, __, X , X , __, __],
        GetStringStatus =>            [__, __, X , X , __, __],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const PHASES: [Phase; 6] = [
        Phase::Instantiated,
        Phase::InitializationMode,
        Phase::StepComplete,
        Phase::Terminated,
        Phase::Error,
        Phase::Fatal,
    ];

    #[test]
    fn rows_map_to_phases_in_order() {
        let set = PhaseSet::row([X, __, X, __, __, X]);
        let inside: Vec<Phase> = PHASES.into_iter().filter(|p| set.contains(*p)).collect();
        assert_eq!(
            inside,
            [Phase::Instantiated, Phase::StepComplete, Phase::Fatal]
        );
    }

    #[test]
    fn only_free_instance_works_after_a_fatal_error() {
        use Function::*;
        for f in [
            SetDebugLogging,
            Reset,
            GetReal,
            SetReal,
            GetFmuState,
            SetFmuState,
            DoStep,
            GetStatus,
        ] {
            assert!(!allowed(f).contains(Phase::Fatal), "{f:?}");
        }
    }

    #[test]
    fn the_error_phase_allows_reading_and_recovery_only() {
        use Function::*;
        for f in [GetReal, GetDirectionalDerivative, Reset, SetFmuState] {
            assert!(allowed(f).contains(Phase::Error), "{f:?}");
        }
        for f in [SetReal, DoStep, Terminate, SetRealInputDerivatives] {
            assert!(!allowed(f).contains(Phase::Error), "{f:?}");
        }
    }

    #[test]
    fn every_function_has_its_own_name() {
        let mut names: Vec<&str> = Function::ALL.iter().map(|f| f.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), Function::ALL.len());
    }

    #[test]
    fn tags_round_trip_except_fatal() {
        for p in PHASES {
            let back = Phase::from_tag(p.tag());
            assert_eq!(back, (p != Phase::Fatal).then_some(p));
        }
        assert_eq!(Phase::from_tag(200), None);
    }
}
