//! The fixed part of the FMU interface, generated at build time from
//! `modelDescription/fixed.xml` so that the code and the XML cannot drift.
//!
//! Per-hull variables (velocities, forces, added mass at infinite frequency, direct damping,
//! power, energy) are added by `fmu-pack`, with value references from
//! [`FIRST_PER_HULL_REFERENCE`] on.

/// A parameter declared in `modelDescription/fixed.xml`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedParameter {
    /// Variable name in the FMU.
    pub name: &'static str,
    /// FMI value reference.
    pub value_reference: u32,
    /// Default value.
    pub start: f64,
    /// Smallest accepted value.
    pub min: f64,
    /// Unit name, declared in the unit definitions.
    pub unit: &'static str,
    /// Human-readable description.
    pub description: &'static str,
}

include!(concat!(env!("OUT_DIR"), "/model_description.rs"));

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_parameters_have_the_documented_defaults() {
        assert_eq!(DEFAULT_RHO, 1025.0);
        assert_eq!(DEFAULT_G, 9.81);
        assert_ne!(VR_RHO, VR_G);
        assert!(PARAMETERS
            .iter()
            .all(|p| p.value_reference < FIRST_PER_HULL_REFERENCE));
        assert!(PARAMETERS.iter().all(|p| UNITS.contains(&p.unit)));
    }

    #[test]
    fn capabilities_match_the_product() {
        let flag = |key: &str| {
            CAPABILITIES
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, v)| *v)
        };
        for key in [
            "canHandleVariableCommunicationStepSize",
            "canGetAndSetFMUstate",
            "canSerializeFMUstate",
            "providesDirectionalDerivative",
            "canInterpolateInputs",
            "canNotUseMemoryManagementFunctions",
        ] {
            assert_eq!(flag(key), Some("true"), "{key}");
        }
        assert_eq!(MAX_OUTPUT_DERIVATIVE_ORDER, 1);
        assert!(FIXED_XML.contains("<fmiModelDescription"));
    }
}
