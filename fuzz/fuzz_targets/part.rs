//! Part files: the input written to a file and read with `oracle::part::load`, the reader
//! behind `verity merge`, then merged alone (a one-share render).

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = verity_fuzz::scratch_file("fuzz.vpart", data);
    let ledger = scenes::budget::Ledger::new();
    if let Ok(part) = oracle::part::load(&path, &ledger) {
        let _ = oracle::part::merge(&[(path, part)], &ledger);
    }
});
