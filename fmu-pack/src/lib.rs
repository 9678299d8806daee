//! Report tools of the hydrofmu pipeline that the FMU does not ship: SVG figures ([`plot`])
//! and the radiation force by direct convolution ([`convolution`], the classic baseline the
//! equivalent network is compared with). Used by the `fmu-pack` binary, the report examples
//! (`cargo run --release -p fmu-pack --example validation`, `... --example performance`) and
//! the convolution benchmark (`cargo bench -p fmu-pack --bench convolution`).
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod convolution;
pub mod plot;
