"""Reference metric maps of two EXR images: FLIP from NVIDIA's flip-evaluator, SSIM from
scikit-image.

Run by compare/tests/metric_reference.rs with the project's venv Python (`.venv/bin/python`,
see requirements.txt: flip-evaluator, scikit-image, OpenEXR, numpy) to check Verity's own FLIP
(compare/src/metrics/flip.rs) and SSIM (compare/src/metrics/ssim.rs) against independent
implementations; not meant to be imported.

    metric_reference.py REF.exr TEST.exr --mode ldr|hdr|ssim [--ppd P]
                        [--start-exposure A --stop-exposure B] --out MAP.exr

Both inputs are read as linear RGB (channels R, G, B; any alpha is ignored) with the
OpenEXR package. LDR mode clamps them to [0, 1] and evaluates LDR-FLIP with
`inputsRGB=False`, i.e. on the linear values themselves (flip-evaluator would otherwise
sRGB-decode them first, as it does for PNG files). HDR mode evaluates HDR-FLIP with the
tool's defaults (ACES tone mapper, automatic exposure range from the reference) unless
both exposures are given. Pixels per degree default to the tool's 67.02.

SSIM mode computes what Verity's SSIM computes (Wang et al. 2004, §III-C): the sRGB-encoded
Rec.709 luminance of the inputs clamped to [0, 1], then skimage.metrics.structural_similarity
with an 11 x 11 Gaussian window of sigma 1.5 (truncate 3.5), population covariances, K1 = 0.01,
K2 = 0.03 and data range 1. Its map is the per-pixel SSIM (not 1 - SSIM); at the border
skimage reflects the image where Verity truncates the window, so only pixels at least 5 from
the border compare, and the mean is skimage's own (over exactly those pixels).

The per-pixel map (no colour map) is written as a float32 EXR whose R, G and B
channels all hold the error. One JSON line goes to stdout:
{"mean": ..., "start_exposure": ..., "stop_exposure": ..., "exposures": ...}
with the tool's own mean and, in LDR and SSIM modes, null for the three exposure fields.
"""

import argparse
import json
import sys

try:
    import numpy as np
    import OpenEXR
    import flip_evaluator
    import skimage.metrics
except ImportError as e:  # the Rust test turns this exit code into "run ./scripts/setup.sh"
    print(f"metric_reference.py: {e}; run ./scripts/setup.sh to install the venv", file=sys.stderr)
    sys.exit(3)


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("reference")
    p.add_argument("test")
    p.add_argument("--mode", required=True, choices=["ldr", "hdr", "ssim"])
    p.add_argument("--ppd", type=float, help="pixels per degree (default: the tool's 67.02)")
    p.add_argument("--start-exposure", type=float)
    p.add_argument("--stop-exposure", type=float)
    p.add_argument("--out", required=True, help="error map EXR to write")
    a = p.parse_args()
    if (a.start_exposure is None) != (a.stop_exposure is None):
        p.error("give both --start-exposure and --stop-exposure, or neither")
    if a.start_exposure is not None and a.mode != "hdr":
        p.error("exposures apply to --mode hdr only")
    if a.ppd is not None and a.mode == "ssim":
        p.error("--ppd applies to FLIP only")
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
                sys.exit(f"metric_reference.py: {path} has no R, G, B channels ({sorted(channels)})")
            rgb = np.stack([channels[c].pixels for c in "RGB"], axis=-1)
    return np.ascontiguousarray(rgb, dtype=np.float32)


def write_map(path, error_map):
    """A float32 EXR with the error in R, G and B."""
    error = np.ascontiguousarray(error_map.reshape(error_map.shape[0], error_map.shape[1]), dtype=np.float32)
    rgb = np.ascontiguousarray(np.repeat(error[..., None], 3, axis=2))
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": rgb}) as f:
        f.write(path)


def srgb_luminance(rgb):
    """sRGB-encoded Rec.709 luminance of the clamped values, in float32 as Verity computes it
    (ITU-R BT.709-6 item 3.2; IEC 61966-2-1 encoding), returned as float64 for skimage."""
    c = np.clip(rgb, 0.0, 1.0)
    y = np.float32(0.2126) * c[..., 0] + np.float32(0.7152) * c[..., 1] + np.float32(0.0722) * c[..., 2]
    y = np.clip(y, 0.0, 1.0).astype(np.float32)
    encoded = np.where(y <= np.float32(0.0031308), np.float32(12.92) * y,
                       np.float32(1.055) * np.power(y, np.float32(1.0 / 2.4)) - np.float32(0.055))
    return encoded.astype(np.float64)


def ssim(reference, test, out):
    """skimage's SSIM with Wang et al.'s settings (module docs); writes the map."""
    mean, ssim_map = skimage.metrics.structural_similarity(
        srgb_luminance(reference), srgb_luminance(test), data_range=1.0, gaussian_weights=True,
        sigma=1.5, use_sample_covariance=False, K1=0.01, K2=0.03, full=True)
    write_map(out, ssim_map)
    print(json.dumps({"mean": float(mean), "start_exposure": None, "stop_exposure": None,
                      "exposures": None}))


def main():
    a = parse_args()
    reference, test = read_rgb(a.reference), read_rgb(a.test)
    if reference.shape != test.shape:
        sys.exit(f"metric_reference.py: sizes differ: {reference.shape} vs {test.shape}")
    if a.mode == "ssim":
        ssim(reference, test, a.out)
        return
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
