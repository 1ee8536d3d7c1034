"""The reference FLIP error map of two EXR images, from NVIDIA's flip-evaluator.

Run by compare/tests/flip_reference.rs with the project's venv Python (`.venv/bin/python`,
see requirements.txt: flip-evaluator, OpenEXR, numpy) to check Verity's own FLIP
(compare/src/metrics/flip.rs) against the reference implementation; not meant to be imported.

    flip_reference.py REF.exr TEST.exr --mode ldr|hdr [--ppd P]
                      [--start-exposure A --stop-exposure B] --out MAP.exr

Both inputs are read as linear RGB (channels R, G, B; any alpha is ignored) with the
OpenEXR package. LDR mode clamps them to [0, 1] and evaluates LDR-FLIP with
`inputsRGB=False`, i.e. on the linear values themselves (flip-evaluator would otherwise
sRGB-decode them first, as it does for PNG files). HDR mode evaluates HDR-FLIP with the
tool's defaults (ACES tone mapper, automatic exposure range from the reference) unless
both exposures are given. Pixels per degree default to the tool's 67.02.

The per-pixel error map (no colour map) is written as a float32 EXR whose R, G and B
channels all hold the error. One JSON line goes to stdout:
{"mean": ..., "start_exposure": ..., "stop_exposure": ..., "exposures": ...}
with the tool's own mean and, in LDR mode, null for the three exposure fields.
"""

import argparse
import json
import sys

try:
    import numpy as np
    import OpenEXR
    import flip_evaluator
except ImportError as e:  # the Rust test turns this exit code into "run ./scripts/setup.sh"
    print(f"flip_reference.py: {e}; run ./scripts/setup.sh to install the venv", file=sys.stderr)
    sys.exit(3)


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("reference")
    p.add_argument("test")
    p.add_argument("--mode", required=True, choices=["ldr", "hdr"])
    p.add_argument("--ppd", type=float, help="pixels per degree (default: the tool's 67.02)")
    p.add_argument("--start-exposure", type=float)
    p.add_argument("--stop-exposure", type=float)
    p.add_argument("--out", required=True, help="error map EXR to write")
    a = p.parse_args()
    if (a.start_exposure is None) != (a.stop_exposure is None):
        p.error("give both --start-exposure and --stop-exposure, or neither")
    if a.start_exposure is not None and a.mode != "hdr":
        p.error("exposures apply to --mode hdr only")
    return a


def read_rgb(path):
    """The R, G, B channels of an EXR as a contiguous H x W x 3 float32 array."""
    with OpenEXR.File(path) as f:
        channels = f.channels()
        for grouped in ("RGB", "RGBA"):
            if grouped in channels:
                rgb = channels[grouped].pixels[..., :3]
                break
        else:
            if not all(c in channels for c in "RGB"):
                sys.exit(f"flip_reference.py: {path} has no R, G, B channels ({sorted(channels)})")
            rgb = np.stack([channels[c].pixels for c in "RGB"], axis=-1)
    return np.ascontiguousarray(rgb, dtype=np.float32)


def write_map(path, error_map):
    """A float32 EXR with the error in R, G and B."""
    error = np.ascontiguousarray(error_map.reshape(error_map.shape[0], error_map.shape[1]), dtype=np.float32)
    rgb = np.ascontiguousarray(np.repeat(error[..., None], 3, axis=2))
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": rgb}) as f:
        f.write(path)


def main():
    a = parse_args()
    reference, test = read_rgb(a.reference), read_rgb(a.test)
    if reference.shape != test.shape:
        sys.exit(f"flip_reference.py: sizes differ: {reference.shape} vs {test.shape}")
    parameters = {}
    if a.ppd is not None:
        parameters["ppd"] = a.ppd
    if a.start_exposure is not None:
        parameters["startExposure"] = a.start_exposure
        parameters["stopExposure"] = a.stop_exposure
    if a.mode == "ldr":
        reference, test = np.clip(reference, 0.0, 1.0), np.clip(test, 0.0, 1.0)
    # evaluate() may convert its inputs in place (sRGB decoding): hand it copies.
    error_map, mean, used = flip_evaluator.evaluate(
        reference.copy(), test.copy(), a.mode.upper(), inputsRGB=False, applyMagma=False,
        computeMeanError=True, parameters=parameters)
    write_map(a.out, np.asarray(error_map))
    hdr = a.mode == "hdr"
    print(json.dumps({
        "mean": float(mean),
        "start_exposure": float(used["startExposure"]) if hdr else None,
        "stop_exposure": float(used["stopExposure"]) if hdr else None,
        "exposures": int(used["numExposures"]) if hdr else None,
    }))


if __name__ == "__main__":
    main()
