//! Crafted resources through `fmi2Instantiate` (docs/STABILITY.md): each case once killed or
//! froze the master's process; now instantiation returns NULL and logs why, naming the limit.
//!
//! Every `unsafe` block frees a component made by [`instantiate`].

use super::*;
use super::{callbacks, instantiate, Log, Unpacked};
use crate::model::Resources;

/// Instantiates `network` in a thread with a 512 KiB stack (a master's worker thread) and
/// returns whether it succeeded and the log.
fn instantiate_in_small_thread(network: String) -> (bool, Vec<(i32, String, String)>) {
    std::thread::Builder::new()
        .stack_size(512 * 1024)
        .spawn(move || {
            let fmu = Unpacked::new(&network, false, "resources");
            let log = Log::default();
            let functions = callbacks(&log);
            let c = instantiate(&fmu, &fmu.uri(), &functions, false);
            let made = !c.is_null();
            if made {
                // SAFETY: `c` was just made by fmi2Instantiate.
                unsafe { fmi2FreeInstance(c) };
            }
            (made, log.into_inner().unwrap())
        })
        .unwrap()
        .join()
        .unwrap()
}

/// The start of a one-DOF coupled network up to its `added_mass_inf`.
const HEAD: &str = r#"<network format_version="1" form="coupled" rho="1025" g="9.81">
<dof name="sway"/>
<added_mass_inf><row>1</row></added_mass_inf>
"#;

fn refused_naming(network: String, limit: &str) {
    let (made, log) = instantiate_in_small_thread(network);
    assert!(!made, "the network was accepted");
    assert!(
        log.iter()
            .any(|(status, _, m)| *status == fmi2Error && m.contains(limit)),
        "no error naming {limit}: {log:?}"
    );
}

#[test]
fn a_network_nested_a_million_levels_deep_is_refused() {
    // Was SIGSEGV in the master's process (10,000 levels sufficed in a 512 KiB thread).
    let mut network = String::from(HEAD);
    network.push_str(&"<branch>".repeat(1_000_000));
    network.push_str(&"</branch>".repeat(1_000_000));
    network.push_str("</network>");
    refused_naming(network, "MAX_DEPTH");
}

#[test]
fn networks_with_too_many_dofs_or_stages_are_refused_before_allocating() {
    // Was an 80 GB allocation that aborted the master's process.
    let mut dofs = String::from(r#"<network format_version="1" form="coupled" rho="1" g="1">"#);
    for k in 0..100_000 {
        dofs.push_str(&format!("<dof name=\"q{k}\"/>"));
    }
    dofs.push_str("<added_mass_inf><row>1</row></added_mass_inf></network>");
    refused_naming(dofs, "MAX_NETWORK_DOFS");

    let stage = r#"<stage mass="1" stiffness="1" damping="1"/>"#;
    let chain = |stages: usize| {
        format!(
            "{HEAD}<branch><direction>1</direction>{}</branch></network>",
            stage.repeat(stages)
        )
    };
    // 20,000 stages were an 80 GB allocation, 1,000 took 14 to 18 s per new step size.
    refused_naming(chain(20_000), "MAX_BRANCH_STAGES");
    refused_naming(chain(1_000), "MAX_BRANCH_STAGES");
    // The largest chain is accepted.
    let (made, log) = instantiate_in_small_thread(chain(crate::network::MAX_BRANCH_STAGES));
    assert!(made, "{log:?}");
    // Too many states in all: 33 branches of 32 stages (2112 > 2048).
    let branch = format!(
        "<branch><direction>1</direction>{}</branch>",
        stage.repeat(32)
    );
    refused_naming(
        format!("{HEAD}{}</network>", branch.repeat(33)),
        "MAX_NETWORK_STATES",
    );
}

#[test]
fn oversized_resource_files_are_refused_before_reading_them() {
    let fmu = Unpacked::new(crate::model::tests::SEED_NETWORK, false, "resources");
    let dir = fmu.uri();
    let path = std::path::PathBuf::from(dir.to_str().unwrap().trim_start_matches("file://"));
    // A sparse file larger than any resource: its length is refused, nothing is read.
    let big = std::fs::File::create(path.join(Resources::EXCITATION_FILE)).unwrap();
    big.set_len(crate::xml::MAX_INPUT_BYTES as u64 + 1).unwrap();
    let Err(error) = Resources::read(&path) else {
        panic!("an oversized excitation.csv was read");
    };
    let error = error.to_string();
    assert!(error.contains("excitation.csv"), "{error}");
    assert!(error.contains("MAX_INPUT_BYTES"), "{error}");
}
