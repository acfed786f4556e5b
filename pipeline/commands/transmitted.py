"""``flexbed transmitted RESULTS.h5 [--reference RESULTS.h5] [--from T]
[--fmax F] [--csv DIR] [--plot FILE.png]``: the force the mounts put into
the base, per mount and summed: time history, narrow-band spectrum and
third-octave bands in N and dB re 1 N; with ``--reference`` (the design
compared against: the rigid bed, the machinery mounted directly), the
insertion loss per band (:mod:`flexbed.analyses.transmitted`)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from flexbed.commands.arguments import number, output_folder
from flexbed.analyses.transmitted import (db, insertion_loss, spectrum, third_octaves,
                                          transmitted_force)
from flexbed.errors import InputError
from flexbed.files.destination import check_destination, write_text
from flexbed.files.results import read_results


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Force transmitted to the base by the mounts: time histories, "
                          "narrow-band and third-octave spectra (N, dB re 1 N), and the "
                          "insertion loss against a reference run.")
    parser.add_argument("results", help="results file written by simulate or run")
    parser.add_argument("--reference", default=None, metavar="RESULTS",
                        help="the reference design's results file (rigid bed, machinery "
                             "mounted directly): insertion loss = its level − this one's")
    parser.add_argument("--from", dest="start", type=number, default=None, metavar="T",
                        help="analyse from T [s] on (skip the transient; default: the "
                             "second half of the run)")
    parser.add_argument("--fmax", type=number, default=None, metavar="F",
                        help="highest third-octave band [Hz] (default: the Nyquist "
                             "frequency)")
    parser.add_argument("--csv", default=None, metavar="DIR",
                        help="write transmitted.csv (time history), spectrum.csv and "
                             "bands.csv into DIR")
    parser.add_argument("--plot", default=None, metavar="FILE",
                        help="write the spectra of the total (z) as a PNG file")


def _analyse(path: str, start: float | None, fmax: float | None):
    tf = transmitted_force(read_results(path))
    t = tf.time
    start = 0.5 * (t[0] + t[-1]) if start is None else start
    if not (math.isfinite(start) and t[0] <= start < t[-1]):
        raise InputError(f"--from {start:g}: must lie in the run, {t[0]:g} to {t[-1]:g} s")
    if fmax is not None and not (math.isfinite(fmax) and fmax >= 1.0):
        raise InputError(f"--fmax {fmax:g}: must be at least 1 Hz (the lowest third-octave "
                         f"band's)")
    sp = spectrum(t, tf.total, start)
    return tf, sp, third_octaves(sp, 1.0, fmax), start


def run(args: argparse.Namespace) -> int:
    output_folder("--csv", args.csv)
    if args.plot:
        check_destination(Path(args.plot))
    tf, sp, bands, start = _analyse(args.results, args.start, args.fmax)
    ref = None
    if args.reference is not None:
        ref = _analyse(args.reference, start, args.fmax)
    late = tf.time >= start
    dyn = tf.total[late] - tf.total[late].mean(axis=0)
    print(f"force into the base, {Path(args.results).name}: {len(tf.mounts)} mounts, "
          f"analysed {sp.start:g}-{tf.time[-1]:g} s ({sp.samples} samples, Hann, "
          f"Δf = {sp.resolution:.4g} Hz)")
    print("        mean [N]      RMS of the dynamic part [N]   [dB re 1 N]   peak line")
    for k in range(3):
        rms = float(np.sqrt(np.mean(dyn[:, k] ** 2)))
        j = int(np.argmax(sp.rms[1:, k])) + 1
        print(f"  F{'xyz'[k]}  {tf.total[late, k].mean():12.6g}  {rms:14.6g}  "
              f"{float(db(rms)):17.2f}      {sp.frequency[j]:.4g} Hz: "
              f"{sp.rms[j, k]:.4g} N ({float(db(sp.rms[j, k])):.2f} dB)")
    il = None
    if ref is not None:
        il = insertion_loss(ref[2], bands)
    print("third-octave bands of the total, dB re 1 N (x, y, z)"
          + (f"; insertion loss against {Path(args.reference).name} [dB]" if il is not None
             else ""))
    for b in range(bands.centre.size):
        lv = db(bands.rms[b])
        row = f"  {bands.nominal[b]:8g} Hz  " + "  ".join(f"{v:7.2f}" for v in lv)
        if il is not None:
            row += "   IL " + "  ".join(f"{v:7.2f}" for v in il[b])
        print(row)
    if args.csv:
        folder = Path(args.csv)
        if folder.exists() and not folder.is_dir():
            raise InputError(f"--csv {args.csv}: is not a folder")
        folder.mkdir(parents=True, exist_ok=True)
        head = "time_s," + ",".join(f"{m}_F{c}_N" for m in tf.mounts for c in "xyz") \
            + ",total_Fx_N,total_Fy_N,total_Fz_N"
        data = np.column_stack([tf.time, tf.per_mount.reshape(tf.time.size, -1), tf.total])
        write_text(folder / "transmitted.csv", _csv(head, data))
        write_text(folder / "spectrum.csv", _csv(
            "frequency_Hz,Fx_rms_N,Fy_rms_N,Fz_rms_N,Fx_dB_re_1N,Fy_dB_re_1N,Fz_dB_re_1N",
            np.column_stack([sp.frequency, sp.rms, db(np.maximum(sp.rms, 1e-300))])))
        cols = [bands.nominal, bands.lower, bands.upper, bands.rms, db(bands.rms)]
        head = ("nominal_Hz,lower_Hz,upper_Hz,Fx_rms_N,Fy_rms_N,Fz_rms_N,Fx_dB_re_1N,"
                "Fy_dB_re_1N,Fz_dB_re_1N")
        if il is not None:
            cols.append(il)
            head += ",IL_x_dB,IL_y_dB,IL_z_dB"
        write_text(folder / "bands.csv", _csv(head, np.column_stack(cols)))
        print(f"wrote {folder}/transmitted.csv, spectrum.csv, bands.csv")
    if args.plot:
        from flexbed.plots.transmitted import plot_transmitted
        cases = {}
        if ref is not None:
            cases[f"reference: {Path(args.reference).name}"] = (ref[1], ref[2])
        cases[Path(args.results).name] = (sp, bands)
        out = plot_transmitted(Path(args.plot), "total force into the base, z", cases, 2,
                               args.fmax)
        print(f"wrote {out}")
    return 0


def _csv(head: str, data: np.ndarray) -> str:
    lines = [head] + [",".join(f"{v:.10g}" for v in row) for row in data]
    return "\n".join(lines) + "\n"
