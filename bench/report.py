#!/usr/bin/python3
"""`make bench`: times snert's stages (`snert bench`) at one thread and at every core, VTK's
vtkFlyingEdges3D (bench/vtk_peer.py, one thread) on the same volumes in the same run, the whole
`snert compare --mode snert` command with its peak memory, and the app (bench/app_stats.py);
prints one table with the issue's targets marked met / not met.

    report.py BUILD_DIR            (BUILD_DIR holds snert)
    QUICK=1 report.py BUILD_DIR    (the CT at the bone iso only; one run per stage; no app)

The CT benchmark volume (512 x 512 x 400 int16 NRRD) is made once into BUILD_DIR/ct512.nrrd by
../shared/tools/upsample_ct.py; without ../shared/data the CT rows are skipped, and it says so.
Times are wall clock: snert's stages are medians of `snert bench --repeat`, FE's of 5 runs after an
untimed one, under glibc's default and under each of snert's two memory policies.
"""
import json, os, re, shutil, subprocess, sys, tempfile, time

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


def snert_bench(snert, volume_args, threads, repeat):
    """One `snert bench` run: its JSON."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "b.json")
        subprocess.run([snert, "bench", *volume_args, "--threads", str(threads), "--repeat",
                        str(repeat), "--quiet", "--json", path], check=True,
                       stdout=subprocess.DEVNULL)
        with open(path) as f:
            return json.load(f)


# glibc's policies of snert's FreedMemory (src/cli/freed_memory.cpp) as environment settings, so
# that flying edges runs under the same one as the snert stage it is compared with.
FRESH_PAGES = {"MALLOC_MMAP_THRESHOLD_": str(256 << 10)}  # Returned: the batch commands'
KEPT_MEMORY = {"MALLOC_MMAP_THRESHOLD_": str(32 << 20),     # Kept: the app's
               "MALLOC_TRIM_THRESHOLD_": str(128 << 20)}


def run_peer(ct, quick, policy=None):
    """vtk_peer.py's JSON, under glibc's default or under `policy` (FRESH_PAGES, KEPT_MEMORY).
    Under FRESH_PAGES every run of flying edges writes into fresh pages, as every timed run of
    `snert bench`'s Marching Cubes does; under KEPT_MEMORY its runs after the first reuse the
    memory the one before freed, as `snert bench`'s "in kept memory" rows do."""
    cmd = [sys.executable, os.path.join(HERE, "vtk_peer.py"), "--runs", "3" if quick else "5"]
    if ct:
        cmd += ["--ct", ct]
    res = subprocess.run(cmd, capture_output=True, text=True, check=True,
                         env={**os.environ, **(policy or {})})
    return json.loads(res.stdout)


def time_compare(snert, ct, iso):
    """Wall clock, peak memory and the meshes' sizes of `snert compare CT --iso ISO --mode
    snert` (all cores), as a user runs it: reading included."""
    cmd = [snert, "compare", ct, "--iso", str(iso), "--mode", "snert", "--quiet", "--json", "-",
           "--no-compactness"]
    timer = shutil.which("time", path="/usr/bin")
    if timer:
        cmd = [timer, "-v"] + cmd
    t0 = time.perf_counter()
    res = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if res.returncode != 0:
        raise RuntimeError(f"snert compare failed:\n{res.stderr[-2000:]}")
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", res.stderr)
    j = json.loads(res.stdout)
    # Positions (3 floats) and triangles (3 indices) of the two meshes, in MiB.
    mesh_mib = sum(12 * (j[k]["vertices"] + j[k]["triangles"]) for k in ("mc", "snert")) / 2**20
    return wall * 1e3, (int(m.group(1)) / 1024 if m else None), mesh_mib


def fmt(v, digits=None):
    if v is None:
        return "-"
    if digits is not None:
        return f"{v:.{digits}f}"
    return f"{v:.0f}" if v >= 100 else f"{v:.1f}"


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build/release"
    quick = os.environ.get("QUICK", "0") not in ("", "0")
    snert = os.path.join(build, "snert")
    cores = os.cpu_count() or 1
    ct = make_ct(build)
    peer = run_peer(ct, quick)
    fe = {k: v["ms"] for k, v in peer["cases"].items()}
    fe_fresh, fe_kept = ({k: v["ms"] for k, v in run_peer(ct, quick, policy)["cases"].items()}
                         for policy in (FRESH_PAGES, KEPT_MEMORY))

    volumes = [("sphere 256^3", ["--size", "256"], "sphere256/iso:0")]
    if ct:
        isos = ISOS[:1] if quick else ISOS
        volumes += [(f"CT iso {iso}", ["--volume", ct, "--iso", str(iso)], f"ct/iso:{iso}")
                    for iso in isos]
    repeat = 1 if quick else 3
    thread_counts = [1] if cores == 1 else [1, cores]
    runs = {(label, t): snert_bench(snert, args, t, repeat)
            for label, args, _ in volumes for t in thread_counts}

    rows = []  # stage, volume, measured, target, verdict

    def add(stage, volume, measured, target, met):
        verdict = "-" if met is None else ("met" if met else "NOT met")
        rows.append((stage, volume, measured, target, verdict))

    many = thread_counts[-1]
    for label, _, key in volumes:
        one, all_ = runs[(label, 1)], runs[(label, many)]
        f, f_fresh, f_kept = fe.get(key), fe_fresh.get(key), fe_kept.get(key)
        # Like against like: each side's fresh pages, and each side's kept memory (bench/README.md,
        # "Fresh pages and kept memory").
        fresh, kept = one["mc_ms"] / f_fresh, one["mc_kept_ms"] / f_kept
        add("Marching Cubes, 1 thread", label,
            f"fresh pages {fmt(one['mc_ms'])} ms, FE {fmt(f_fresh)} ms: {fresh:.2f}x; kept memory "
            f"{fmt(one['mc_kept_ms'])} ms, FE {fmt(f_kept)} ms: {kept:.2f}x FE's time",
            "<= 0.5x (2x FE's throughput)", max(fresh, kept) <= 0.5)
        if many > 1:
            speedup = one["mc_ms"] / all_["mc_ms"]
            kept_speedup = one["mc_kept_ms"] / all_["mc_kept_ms"]
            add(f"Marching Cubes, {many} threads", label,
                f"fresh {fmt(all_['mc_ms'])} ms: {speedup:.2f}x faster; kept "
                f"{fmt(all_['mc_kept_ms'])} ms: {kept_speedup:.2f}x", ">= 1.8x faster",
                min(speedup, kept_speedup) >= 1.8)
        add("net build, 1 thread", label,
            f"fresh {fmt(one['net_ms'])} ms = {one['net_ms'] / one['mc_ms']:.2f}x our MC; kept "
            f"{fmt(one['net_kept_ms'])} ms = {one['net_kept_ms'] / one['mc_kept_ms']:.2f}x",
            "<= our MC", max(one["net_ms"] / one["mc_ms"],
                             one["net_kept_ms"] / one["mc_kept_ms"]) <= 1)
        add("SNERT iteration, 1 thread", label,
            f"{fmt(one['relax_ns_per_node'])} ns/node ({one['nodes']} nodes)", "<= 25 ns/node",
            one["relax_ns_per_node"] <= 25)
        add("  with --gradient central (the paper's)", label,
            f"{fmt(one['relax_central_ns_per_node'])} ns/node", "-", None)
        if many > 1:
            speedup = one["relax_ms"] / all_["relax_ms"]
            add(f"SNERT iteration, {many} threads", label,
                f"{fmt(all_['relax_ns_per_node'])} ns/node: {speedup:.2f}x faster",
                ">= 1.8x faster", speedup >= 1.8)
        for t, run in ((1, one), (many, all_)) if many > 1 else ((1, one),):
            iterations = run["metrics_ms"] / run["relax_ms"]
            add(f"metrics of a mesh, {t} thread{'s' if t > 1 else ''}", label,
                f"{fmt(run['metrics_ms'])} ms = {iterations:.1f} iterations "
                f"(+ distance to MC {fmt(run['to_mc_ms'])} ms)", "<= 2 iterations",
                iterations <= 2)
        add(f"compare --mode snert after reading, {many} thread{'s' if many > 1 else ''}",
            label, f"{fmt(all_['compare_ms'])} ms = {all_['compare_ms'] / f:.1f}x FE", "-",
            None)
    if ct:
        for iso in ISOS[:1] if quick else ISOS:
            wall, peak, mesh_mib = time_compare(snert, ct, iso)
            f = fe[f"ct/iso:{iso}"]
            add("snert compare --mode snert (command)", f"CT iso {iso}",
                f"{fmt(wall)} ms = {wall / f:.1f}x FE", "<= 4x FE", wall / f <= 4.0)
            dims = peer.get("ct_dims", [512, 512, 400])
            budget = 4 * dims[0] * dims[1] * dims[2] / 2**20 + 3 * mesh_mib
            add("  its peak memory", f"CT iso {iso}",
                f"{fmt(peak)} MiB (float volume + 3x meshes = {budget:.0f} MiB)",
                "<= float volume + 3x meshes", None if peak is None else peak <= budget)

    print(f"snert against VTK {peer['vtk']} vtkFlyingEdges3D ({peer['smp_backend']}, "
          f"{peer['threads']} thread), same run; {cores} cores"
          + ("; QUICK=1" if quick else ""))
    head = ("stage", "volume", "measured", "target", "")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    if not ct:
        print("(no CT rows: ../shared/data is absent)")

    app_stats = os.path.join(HERE, "app_stats.py")
    if not quick and os.path.exists(app_stats):
        print()
        res = subprocess.run([sys.executable, app_stats, build], capture_output=True, text=True)
        if res.returncode != 0:
            print(f"app: bench/app_stats.py failed:\n{res.stderr[-2000:]}")
        else:
            print(res.stdout.rstrip())
        if ct:
            # The app on the CT at the bone iso, against flying edges' one-thread time there.
            print()
            res = subprocess.run([sys.executable, app_stats, build, "--volume", ct, "--iso",
                                  str(ISOS[0])], capture_output=True, text=True)
            if res.returncode != 0:
                print(f"app on the CT: bench/app_stats.py failed:\n{res.stderr[-2000:]}")
            else:
                print(res.stdout.rstrip())
                stats = json.loads(res.stdout.strip().splitlines()[-1])
                f = fe[f"ct/iso:{ISOS[0]}"] / 1e3
                shown, done = stats["load_to_mc_shown_s"], stats["load_to_done_s"]
                print(f"  app on the CT: MC shown {shown:.2f} s after the load = {shown / f:.1f}x FE "
                      f"(target <= 3x: {'met' if shown <= 3 * f else 'NOT met'}); the whole "
                      f"comparison {done:.1f} s after it = {done / f:.0f}x FE (target <= 10x: "
                      f"{'met' if done <= 10 * f else 'NOT met'})")


if __name__ == "__main__":
    main()
