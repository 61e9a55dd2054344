//! The paper's §7.2: the double spherical pendulum over the paper's run (`T = 100`, `N = 10⁴`),
//! integrated with the reduced (+) equations (4.6). Prints a summary (energies, momentum, Newton
//! statistics, wall time) and writes Figure 3, the top of Figure 4 and the data (CSV).
//!
//! ```text
//! cargo run --release --example double_spherical_pendulum [-- --out DIR]
//! ```

mod common;

use std::error::Error;

use common::double_spherical_pendulum as dsp;

fn main() -> Result<(), Box<dyn Error>> {
    let out = common::output_dir(
        "double_spherical_pendulum",
        "target/dirac-figures/double_spherical_pendulum",
    )?;
    let run = dsp::run()?;
    dsp::report(&run);
    dsp::pole_error_path();
    dsp::write_figures(&run, &out)?;
    println!("\nFigures 3 and 4, CSV: {}", out.display());
    Ok(())
}
