#!/usr/bin/env python3
"""The app's responsiveness against the CLI doing the same work.

    bench/app_stats.py BUILD_DIR [--volume FILE] [--iso V] [--iterations K] [--window WxH]

Runs `snert compare` (wall time) and `snert gui --stats` (a scripted session in a real window
under Xvfb: the comparison, 6 single steps, 2 s of turning the camera) on the same input, and
prints one table and then one JSON object to stdout. Targets: the app's whole comparison within
2x the CLI's time, a step shown within 0.3 s, turning at >= 10 fps, UI frames under 50 ms.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data")


def run_cli(snert, volume, iso, iterations):
    with tempfile.TemporaryDirectory() as tmp:
        start = time.monotonic()
        subprocess.run([snert, "compare", volume, "--iso", str(iso), "--mode", "snert",
                        "--iterations", str(iterations), "--json", os.path.join(tmp, "c.json"),
                        "--no-compactness"],
                       check=True, stdout=subprocess.DEVNULL)
        return time.monotonic() - start


def run_app(snert, volume, iso, iterations, window):
    command = [snert, "gui", volume, "--iso", str(iso), "--mode", "snert", "--iterations",
               str(iterations), "--window", window, "--stats"]
    if os.environ.get("DISPLAY") and not os.environ.get("SNERT_STATS_XVFB"):
        prefix = []
    elif shutil.which("xvfb-run"):
        prefix = ["xvfb-run", "-a", "-s", "-screen 0 %sx24" % window]
    else:
        sys.exit("app_stats.py: needs a display or xvfb-run")
    out = subprocess.run(prefix + command, check=True, capture_output=True, text=True).stdout
    lines = [line for line in out.splitlines() if line.startswith("{")]
    if not lines:
        sys.exit("app_stats.py: no JSON from snert gui --stats:\n" + out)
    return json.loads(lines[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir")
    parser.add_argument("--volume", default=os.path.join(DATA, "FLAIR.nrrd"))
    parser.add_argument("--iso", type=float, default=40)
    parser.add_argument("--iterations", type=int, default=20)
    parser.add_argument("--window", default="1280x800")
    args = parser.parse_args()
    snert = os.path.join(args.build_dir, "snert")
    if not os.path.exists(snert):
        sys.exit("app_stats.py: %s not found (build it first)" % snert)

    cli_s = run_cli(snert, args.volume, args.iso, args.iterations)
    app = run_app(snert, args.volume, args.iso, args.iterations, args.window)
    ratio = app["comparison_s"] / cli_s if cli_s > 0 else float("inf")
    rows = [
        ("CLI compare (wall)", "%.2f s" % cli_s, ""),
        ("app: whole comparison", "%.2f s" % app["comparison_s"],
         "%.1fx CLI (target <= 2x)" % ratio),
        ("app: loaded -> MC shown", "%.2f s" % app["load_to_mc_shown_s"], ""),
        ("app: UI frame while computing", "%.1f / %.1f ms" % (app["frame_ms_mean"],
                                                              app["frame_ms_max"]),
         "mean / max (target < 50 ms); %d of %d frames over 50 ms; the first %.0f ms, the "
         "largest after it %.0f ms" % (app["frames_over_50_ms"], app["frames"],
                                       app["first_frame_ms"], app["frame_ms_max_later"])),
        ("app: largest part of a mesh", "%.1f ms" % app["part_ms_max"],
         "drawn between frames or in one (%d parts)" % app["part_draws"]),
        ("app: step shown", "%.3f / %.3f s" % (app["step_latency_s_mean"],
                                              app["step_latency_s_max"]),
         "mean / max (target <= 0.3 s)"),
        ("app: turning the camera", "%.1f fps" % app["turn_fps"], "target >= 10 fps"),
    ]
    print("%s, iso %g, %d iterations: %d + %d triangles" %
          (os.path.basename(args.volume), args.iso, args.iterations, app["mc_triangles"],
           app["net_triangles"]))
    for name, value, note in rows:
        print("  %-31s %-16s %s" % (name, value, note))
    result = dict(app, cli_compare_s=round(cli_s, 3), comparison_vs_cli=round(ratio, 2),
                  volume=os.path.basename(args.volume), iso=args.iso, iterations=args.iterations,
                  targets_met={"comparison_within_2x_cli": ratio <= 2.0,
                               "step_within_0_3_s": app["step_latency_s_max"] <= 0.3,
                               "turn_at_least_10_fps": app["turn_fps"] >= 10.0,
                               "frames_under_50_ms": app["frame_ms_max"] < 50.0})
    print(json.dumps(result))


if __name__ == "__main__":
    main()
