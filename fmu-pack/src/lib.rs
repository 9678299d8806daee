//! Report tools of the hydrofmu pipeline that the FMU does not ship: SVG figures ([`plot`]).
//! Used by the `fmu-pack` binary and the report examples (`cargo run --release -p fmu-pack
//! --example validation`, `... --example performance`). The radiation force by direct
//! convolution, the baseline the equivalent network is compared with, lives beside its
//! benchmark (`benches/common/convolution.rs`, run by `cargo bench -p fmu-pack --bench
//! convolution`, tested by `tests/convolution.rs`).
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod plot;
