//! The radiation force by direct convolution (the benchmark baseline,
//! `benches/common/convolution.rs`) against the network's exact step: its unit tests run here.

// Its unit tests run here; not every item is used by them.
#[allow(dead_code)]
#[path = "../benches/common/convolution.rs"]
mod convolution;

#[test]
fn the_baseline_refuses_a_zero_step() {
    let network = hydrofmu::network::Network::from_xml_str(
        include_str!("../examples/networks/seed_2dof.xml"),
        "seed",
    )
    .unwrap();
    let ss = network.state_space().unwrap();
    assert!(convolution::ConvolutionForce::new(&ss, 0.0, 10).is_err());
}
