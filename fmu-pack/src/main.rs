//! `fmu-pack`: packs one hydrofmu FMU archive per hull geometry.

fn main() {
    println!(
        "fmu-pack {}: {} log categories declared",
        env!("CARGO_PKG_VERSION"),
        hydrofmu::model_description::LOG_CATEGORIES.len()
    );
}
