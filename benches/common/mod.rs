//! Shared bench inputs.

/// The DOFs of the default semicircle network.
pub const MODES: [&str; 9] = [
    "sway", "heave", "roll", "cb1", "cb2", "cb3", "cb4", "cb5", "cb6",
];

/// A synthetic 9-DOF excitation table (docs/WAVES.md format; R = 1 m, 201 log-spaced kR over
/// 0.01..10, headings 0 and 180) with smooth values; the cost of a sea does not depend on them.
pub fn synthetic_excitation_csv() -> String {
    let mut text = format!(
        "# modes: {}\n# convention: exp(+i omega t)\n# R: 1 m\n\
         # length exponents: 0 0 1 0 0 1 0 0 1\nkR,j,heading,re,im\n",
        MODES.join(" ")
    );
    for i in 0..201 {
        let kr = 0.01 * 1000f64.powf(i as f64 / 200.0);
        for heading in [0, 180] {
            for j in 0..MODES.len() {
                let magnitude = (1.0 + j as f64) * (-kr).exp();
                let phase = -kr * (1.0 + 0.1 * j as f64);
                text += &format!(
                    "{kr:e},{},{heading},{:e},{:e}\n",
                    j + 1,
                    magnitude * phase.cos(),
                    magnitude * phase.sin()
                );
            }
        }
    }
    text
}
