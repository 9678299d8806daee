//! Turns `modelDescription/fixed.xml` into Rust constants, so the code and the XML cannot drift.
//!
//! The generated file (`$OUT_DIR/model_description.rs`) is included by
//! `src/fmu/description.rs`. Any malformed or inconsistent declaration fails the build with a
//! message naming the file, the line and the problem.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

// The library's XML reader; its writing helpers are not needed here.
#[path = "src/xml.rs"]
#[allow(dead_code)]
mod xml;

const SOURCE: &str = "modelDescription/fixed.xml";
/// Value references below this bound belong to the fixed variables.
const FIRST_PER_HULL_REFERENCE: u32 = 100;
const REQUIRED_CAPABILITIES: [&str; 9] = [
    "canHandleVariableCommunicationStepSize",
    "canInterpolateInputs",
    "maxOutputDerivativeOrder",
    "canRunAsynchronuously",
    "canBeInstantiatedOnlyOncePerProcess",
    "canNotUseMemoryManagementFunctions",
    "canGetAndSetFMUstate",
    "canSerializeFMUstate",
    "providesDirectionalDerivative",
];

struct Variable {
    name: String,
    value_reference: u32,
    causality: String,
    variability: String,
    description: String,
    /// `<Integer>` rather than `<Real>`.
    integer: bool,
    start: f64,
    min: f64,
    /// Largest accepted value (`max`; unbounded for a Real without one).
    max: f64,
    /// Unit name (empty for Integers, which have none in FMI 2.0).
    unit: String,
    line: usize,
}

fn main() {
    println!("cargo:rerun-if-changed={SOURCE}");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/xml.rs");
    let text = match std::fs::read_to_string(SOURCE) {
        Ok(text) => text,
        Err(err) => fail(0, &format!("cannot read the file: {err}")),
    };
    let generated = generate(&text);
    let out_dir = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR for build scripts");
    let out = Path::new(&out_dir).join("model_description.rs");
    if let Err(err) = std::fs::write(&out, generated) {
        fail(0, &format!("cannot write {}: {err}", out.display()));
    }
}

fn fail(line: usize, problem: &str) -> ! {
    if line > 0 {
        eprintln!("error: {SOURCE}:{line}: {problem}");
    } else {
        eprintln!("error: {SOURCE}: {problem}");
    }
    std::process::exit(1);
}

/// Stops the build at a problem of an element.
fn check<T>(result: Result<T, xml::XmlError>) -> T {
    result.unwrap_or_else(|e| fail(e.line, &e.message))
}

fn generate(text: &str) -> String {
    let root = check(xml::parse(text));
    let mut root_seen = false;
    let mut capabilities: Vec<(String, String)> = Vec::new();
    let mut units: Vec<String> = Vec::new();
    let mut categories: Vec<(String, String)> = Vec::new();
    let mut variables: Vec<Variable> = Vec::new();
    let mut default_experiment: Option<(f64, f64, f64)> = None;
    let mut open_variable: Option<&xml::Element> = None;
    for element in root.descendants() {
        let line = element.line;
        let get = |key: &str| check(element.required(key));
        let number = |key: &str| check(element.required_number(key));
        match element.name.as_str() {
            "fmiModelDescription" => {
                root_seen = true;
                let version = get("fmiVersion");
                if version != "2.0" {
                    fail(line, &format!("fmiVersion is '{version}', expected '2.0'"));
                }
            }
            "CoSimulation" => capabilities = element.attributes.clone(),
            "Unit" => {
                let unit = get("name").to_string();
                if units.contains(&unit) {
                    fail(line, &format!("unit '{unit}' is declared twice"));
                }
                units.push(unit);
            }
            "Category" => {
                let category = get("name").to_string();
                let description = get("description").to_string();
                if categories.iter().any(|(c, _)| *c == category) {
                    fail(
                        line,
                        &format!("log category '{category}' is declared twice"),
                    );
                }
                categories.push((category, description));
            }
            "DefaultExperiment" => {
                let start = number("startTime");
                let stop = number("stopTime");
                let step = number("stepSize");
                if stop <= start || step <= 0.0 {
                    fail(
                        line,
                        "DefaultExperiment needs stopTime > startTime and stepSize > 0",
                    );
                }
                default_experiment = Some((start, stop, step));
            }
            "ScalarVariable" => open_variable = Some(element),
            "Real" | "Integer" => {
                let integer = element.name == "Integer";
                let Some(variable) = open_variable.take() else {
                    fail(
                        line,
                        &format!("<{}> outside a <ScalarVariable>", element.name),
                    );
                };
                let field = |key: &str| check(variable.required(key));
                let value_reference = field("valueReference").parse::<u32>().unwrap_or_else(|_| {
                    fail(variable.line, "valueReference is not an unsigned integer")
                });
                let start = number("start");
                // An <Integer> declares both bounds; a <Real> either or none (unbounded).
                let bound = |key: &str, unbounded: f64| match element.attribute(key) {
                    None if !integer => unbounded,
                    _ => number(key),
                };
                let min = bound("min", f64::NEG_INFINITY);
                let max = bound("max", f64::INFINITY);
                if start < min || start > max {
                    fail(line, &format!("start {start} is outside [{min}, {max}]"));
                }
                if integer && [start, min, max].iter().any(|x| x.fract() != 0.0) {
                    fail(line, "an <Integer>'s start, min and max must be integers");
                }
                variables.push(Variable {
                    name: field("name").to_string(),
                    value_reference,
                    causality: field("causality").to_string(),
                    variability: field("variability").to_string(),
                    description: field("description").to_string(),
                    integer,
                    start,
                    min,
                    max,
                    unit: if integer {
                        String::new()
                    } else {
                        get("unit").to_string()
                    },
                    line,
                });
            }
            _ => {}
        }
    }
    if !root_seen {
        fail(0, "no <fmiModelDescription> root element");
    }
    for required in REQUIRED_CAPABILITIES {
        if !capabilities.iter().any(|(k, _)| k == required) {
            fail(0, &format!("<CoSimulation> must declare '{required}'"));
        }
    }
    let Some(default_experiment) = default_experiment else {
        fail(0, "no <DefaultExperiment>");
    };
    let mut references = BTreeSet::new();
    for variable in &variables {
        if !references.insert(variable.value_reference) {
            fail(
                variable.line,
                &format!("valueReference {} is used twice", variable.value_reference),
            );
        }
        if variable.value_reference >= FIRST_PER_HULL_REFERENCE {
            fail(
                variable.line,
                &format!("fixed variables need valueReference < {FIRST_PER_HULL_REFERENCE}"),
            );
        }
        if !variable.integer && !units.contains(&variable.unit) {
            fail(
                variable.line,
                &format!(
                    "unit '{}' is not declared in <UnitDefinitions>",
                    variable.unit
                ),
            );
        }
        if variable.causality != "parameter" || variable.variability != "fixed" {
            fail(
                variable.line,
                "fixed variables must be parameters with variability 'fixed'",
            );
        }
    }
    for required in ["rho", "g"] {
        if !variables.iter().any(|v| v.name == required) {
            fail(0, &format!("the parameter '{required}' is not declared"));
        }
    }
    for required in [
        "logStatusError",
        "logStatusWarning",
        "logEvents",
        "logCalls",
    ] {
        if !categories.iter().any(|(c, _)| c == required) {
            fail(0, &format!("the log category '{required}' is not declared"));
        }
    }

    let mut out = String::new();
    let flag = |key: &str| {
        capabilities
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    let _ = writeln!(out, "// Generated by build.rs from {SOURCE}. Do not edit.");
    let _ = writeln!(
        out,
        "/// The text of `{SOURCE}`, copied into every packed modelDescription.xml."
    );
    let _ = writeln!(out, "pub const FIXED_XML: &str = include_str!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/{SOURCE}\"));");
    let _ = writeln!(
        out,
        "/// First value reference available to per-hull variables."
    );
    let _ = writeln!(
        out,
        "pub const FIRST_PER_HULL_REFERENCE: u32 = {FIRST_PER_HULL_REFERENCE};"
    );
    let _ = writeln!(out, "/// Co-simulation capability flags, as declared.");
    let _ = writeln!(out, "pub const CAPABILITIES: &[(&str, &str)] = &[");
    for key in REQUIRED_CAPABILITIES {
        let _ = writeln!(out, "    ({key:?}, {:?}),", flag(key));
    }
    let _ = writeln!(out, "];");
    let max_order = flag("maxOutputDerivativeOrder")
        .parse::<u32>()
        .unwrap_or_else(|_| fail(0, "maxOutputDerivativeOrder is not an unsigned integer"));
    let _ = writeln!(out, "/// Highest output derivative order the FMU provides.");
    let _ = writeln!(
        out,
        "pub const MAX_OUTPUT_DERIVATIVE_ORDER: u32 = {max_order};"
    );
    let _ = writeln!(out, "/// Declared units.");
    let _ = writeln!(out, "pub const UNITS: &[&str] = &{units:?};");
    let _ = writeln!(out, "/// Declared log categories, with their descriptions.");
    let _ = writeln!(
        out,
        "pub const LOG_CATEGORIES: &[(&str, &str)] = &{categories:?};"
    );
    let _ = writeln!(
        out,
        "/// Default experiment: start time, stop time, step size (s)."
    );
    let _ = writeln!(
        out,
        "pub const DEFAULT_EXPERIMENT: (f64, f64, f64) = ({:?}, {:?}, {:?});",
        default_experiment.0, default_experiment.1, default_experiment.2
    );
    let _ = writeln!(out, "/// The fixed parameters.");
    let _ = writeln!(out, "pub const PARAMETERS: &[FixedParameter] = &[");
    for v in &variables {
        let _ = writeln!(
            out,
            "    FixedParameter {{ name: {:?}, value_reference: {}, integer: {}, start: {:?}, min: {}, max: {}, unit: {:?}, description: {:?} }},",
            v.name, v.value_reference, v.integer, v.start,
            if v.min.is_finite() { format!("{:?}", v.min) } else { "f64::NEG_INFINITY".into() },
            if v.max.is_finite() { format!("{:?}", v.max) } else { "f64::INFINITY".into() },
            v.unit, v.description
        );
    }
    let _ = writeln!(out, "];");
    for v in &variables {
        let _ = writeln!(out, "/// Value reference of `{}`.", v.name);
        let _ = writeln!(
            out,
            "pub const VR_{}: u32 = {};",
            constant_name(&v.name),
            v.value_reference
        );
        let _ = writeln!(out, "/// Default of `{}` ({}).", v.name, v.unit);
        let _ = writeln!(
            out,
            "pub const DEFAULT_{}: f64 = {:?};",
            constant_name(&v.name),
            v.start
        );
    }
    out
}

/// `wave.kind` -> `WAVE_KIND`: the constant names of a variable.
fn constant_name(name: &str) -> String {
    name.to_uppercase().replace('.', "_")
}
