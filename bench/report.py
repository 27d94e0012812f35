#!/usr/bin/python3
"""`make bench`: times snert (snert_bench, Google Benchmark) and VTK's vtkFlyingEdges3D
(bench/vtk_peer.py, one thread) on the same volumes in one run, and prints one table with the
issue's speed targets marked met / not met.

    report.py BUILD_DIR            (BUILD_DIR holds snert_bench and snert)
    QUICK=1 report.py BUILD_DIR    (the CT at the bone iso only, for `snert compare`; fewer runs)

The CT benchmark volume (512 x 512 x 400 int16 NRRD) is made once into BUILD_DIR/ct512.nrrd by
../shared/tools/upsample_ct.py; without ../shared/data the CT rows are skipped, and it says so.
Times are wall clock; snert's are medians of Google Benchmark repetitions, FE's medians of 5.
"""
import json, os, re, shutil, subprocess, sys, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(ROOT, "..", "shared")
CT_SOURCE = os.path.join(SHARED, "data", "totalseg_ct_abdomen", "example_ct_sm.nii.gz")
ISOS = (200, -500)  # bone, skin


def make_ct(build):
    out = os.path.join(build, "ct512.nrrd")
    if os.path.exists(out):
        return out
    if not os.path.exists(CT_SOURCE):
        print(f"bench: {CT_SOURCE} absent: the CT rows are skipped", file=sys.stderr)
        return None
    subprocess.run([sys.executable, os.path.join(SHARED, "tools", "upsample_ct.py"), CT_SOURCE,
                    out + ".part"], check=True)
    os.replace(out + ".part", out)
    return out


def run_snert_bench(build, ct, quick):
    env = dict(os.environ)
    if ct:
        env["SNERT_BENCH_CT"] = ct
    cmd = [os.path.join(build, "snert_bench"), "--benchmark_format=json",
           "--benchmark_filter=/256|CT", "--benchmark_repetitions=%d" % (2 if quick else 3),
           "--benchmark_report_aggregates_only=true"]
    if quick:
        cmd.append("--benchmark_min_time=0.2")
    res = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    medians = {}
    for b in json.loads(res.stdout)["benchmarks"]:
        if b.get("aggregate_name") == "median":
            medians[b["run_name"]] = b
    return medians


def run_peer(ct, quick):
    cmd = [sys.executable, os.path.join(HERE, "vtk_peer.py"), "--runs", "3" if quick else "5"]
    if ct:
        cmd += ["--ct", ct]
    res = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(res.stdout)


def time_compare(build, ct, iso):
    """Wall clock and peak memory of `snert compare CT --iso ISO --mode snert`."""
    cmd = [os.path.join(build, "snert"), "compare", ct, "--iso", str(iso), "--mode", "snert"]
    timer = shutil.which("time", path="/usr/bin")
    if timer:
        cmd = [timer, "-v"] + cmd
    t0 = time.perf_counter()
    res = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if res.returncode != 0:
        raise RuntimeError(f"snert compare failed:\n{res.stderr[-2000:]}")
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", res.stderr)
    return wall * 1e3, (int(m.group(1)) / 1024 if m else None)


def fmt_ms(ms):
    return "-" if ms is None else (f"{ms:.0f}" if ms >= 100 else f"{ms:.1f}")


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build/release"
    quick = os.environ.get("QUICK", "0") not in ("", "0")
    ct = make_ct(build)
    snert = run_snert_bench(build, ct, quick)
    peer = run_peer(ct, quick)
    fe = {k: v["ms"] for k, v in peer["cases"].items()}

    rows = []  # stage, volume, snert ms, FE ms, ratio text, target, met

    def find(name):  # run names go on with /iterations:1/repeats:N/real_time
        return next((b for k, b in snert.items() if k.startswith(name + "/")), None)

    def ms(name):
        b = find(name)
        return None if b is None else b["real_time"]  # the unit is ms (bench sources)

    def add(stage, volume, s_ms, f_ms, target, met, extra=""):
        ratio = f"{s_ms / f_ms:.2f}" if s_ms is not None and f_ms else "-"
        verdict = "-" if met is None else ("met" if met else "NOT met")
        rows.append((stage, volume, fmt_ms(s_ms), fmt_ms(f_ms), ratio, target + extra, verdict))

    volumes = [("sphere 256^3", "/256", "sphere256/iso:0")]
    if ct:
        volumes += [(f"CT 512x512x400 iso {iso}", f"/iso:{iso}", f"ct/iso:{iso}") for iso in ISOS]
    for label, suffix, key in volumes:
        prefix = "BM_" if suffix == "/256" else "BM_CT_"
        mc = ms(prefix + "MarchingCubes" + suffix)
        add("Marching Cubes", label, mc, fe.get(key), "snert/FE <= 0.5 (2x FE throughput)",
            None if mc is None else mc / fe[key] <= 0.5)
    for label, suffix, key in volumes:
        prefix = "BM_" if suffix == "/256" else "BM_CT_"
        mc, net = ms(prefix + "MarchingCubes" + suffix), ms(prefix + "SurfaceNetBuild" + suffix)
        add("net build", label, net, fe.get(key), f"<= our MC ({fmt_ms(mc)} ms)",
            None if net is None or mc is None else net <= mc)
    for label, suffix, key in volumes:
        prefix = "BM_" if suffix == "/256" else "BM_CT_"
        b = find(prefix + "RelaxStep" + suffix)
        if b is None:
            continue
        if "ns/node" in b:
            ns = b["ns/node"]
        else:  # the sphere benchmark reports Mnodes/s
            ns = 1e3 / b["Mnodes/s"]
        add("one SNERT iteration", label, b["real_time"], fe.get(key), "<= 25 ns/node",
            ns <= 25.0, f" (got {ns:.1f})")
    if ct:
        for iso in ISOS[:1] if quick else ISOS:
            wall, peak = time_compare(build, ct, iso)
            key = f"ct/iso:{iso}"
            mem = f", peak {peak:.0f} MiB" if peak else ""
            add("snert compare --mode snert", f"CT 512x512x400 iso {iso}", wall, fe.get(key),
                "snert/FE <= 4", wall / fe[key] <= 4.0, f" (wall{mem})")

    head = ("stage", "volume", "snert ms", "FE ms (1 thread)", "snert/FE", "target", "")
    print(f"snert vs VTK {peer['vtk']} vtkFlyingEdges3D ({peer['smp_backend']}, "
          f"{peer['threads']} thread); snert with its default threads "
          f"({os.cpu_count()} cores: src/core/parallel.h has no thread-count knob)"
          + ("; QUICK=1" if quick else ""))
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    if not ct:
        print("(no CT rows: ../shared/data is absent)")


if __name__ == "__main__":
    main()
