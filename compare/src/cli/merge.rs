//! `verity merge PART… --out FILE.exr`: the parts of one render (`verity render --part K/N`)
//! assembled into the EXR a single `verity render` writes, bit for bit in every channel and in
//! the header but for `seconds` (the parts' sum) and `command_line` (this command's).

use std::path::PathBuf;

use clap::Args;
use scenes::budget::Ledger;

use super::args::{exr_output, parse_exposure};
use super::CliError;

/// Flags of `verity merge`.
#[derive(Args, Clone, Debug)]
pub struct MergeArgs {
    /// The part files (.vpart), every share of one render exactly once, in any order.
    #[arg(value_name = "PART", required = true)]
    pub parts: Vec<PathBuf>,

    /// Output EXR; the PNG preview goes beside it with the extension .png.
    #[arg(long, value_name = "FILE.exr")]
    pub out: PathBuf,

    /// Exposure of the PNG preview in stops (the EXR is not scaled).
    #[arg(long, value_name = "STOPS", default_value_t = 0.0, allow_negative_numbers = true,
          value_parser = parse_exposure)]
    pub exposure: f32,
}

/// Runs `verity merge`; `command_line` goes into the EXR header.
pub fn run(args: &MergeArgs, command_line: &str) -> Result<(), CliError> {
    let out = exr_output(args.out.clone())?;
    let ledger = Ledger::new();
    let parts = args
        .parts
        .iter()
        .map(|p| oracle::part::load(p, &ledger).map(|part| (p.clone(), part)))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| CliError::input(e.to_string()))?;
    let mut image = oracle::part::merge(&parts, &ledger).map_err(|e| CliError::input(e.to_string()))?;
    image.set_attribute("command_line", command_line);
    image.write_exr(&out).map_err(|e| CliError::run(e.to_string()))?;
    image
        .write_png_preview(out.with_extension("png"), args.exposure)
        .map_err(|e| CliError::run(e.to_string()))?;
    println!(
        "merged {} parts: {}x{}, {} spp, {} s of rendering -> {}",
        parts.len(),
        image.width,
        image.height,
        image.attribute("spp").unwrap_or("?"),
        image.attribute("seconds").unwrap_or("?"),
        out.display()
    );
    Ok(())
}
