//! Study plans: the input written as a plan file in the scratch folder and read with
//! `compare::study::jobs::read_plan`, the reader behind `verity run-job` and `report --from`
//! (JSON, then the check of the folders it writes to, its hashes and its jobs' outputs); a
//! plan it accepts is asked what is unfinished, which reads the cache entries it names. No
//! job is run: the targets must write nowhere but the scratch folder.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = verity_fuzz::scratch_file("studies/fuzz-plan.json", data);
    if let Ok(plan) = compare::study::jobs::read_plan(&path) {
        let _ = compare::study::jobs::unfinished(&plan);
        let _ = compare::study::jobs::job(&plan, "ground_truth");
    }
});
