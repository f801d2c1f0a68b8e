#!/usr/bin/python3
"""pd-pack's CPU time and peak memory against the model size (issue 29 item 4), two builds side by
side: each size is packed --repeat times with each binary, alternating, and the table gives the
process CPU (user + sys) min / median, the peak RSS and the wall time (min), and whether the two
files hold the same bits (h5diff without /provenance).

    workflows/bench/startup/pack_scale.py --new build/bin --old base/bin --out /tmp/pack_scale \\
        --sizes 2d:5e-4,2d:3.5e-4,2d:2.5e-4,3d:6.3e-4 --repeat 3

2d:H packs plate2d.json at mesh size H (5e-4: 1.0e6 nodes), 3d:H block3d.json (6.3e-4: 1.03e6
nodes). Sizes above the memory guard need --max-nodes (given here as 2e7).
"""
import argparse
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def pack(binary, scene, h, out):
    t = out + ".time"
    cmd = ["/usr/bin/time", "-f", "%U %S %M %e", "-o", t, os.path.join(binary, "pd-pack"),
           scene, "--set", "discretization.mesh_size=%s" % h, "-o", out, "--overwrite", "-q",
           "--max-nodes", "20000000"]
    subprocess.run(cmd, check=True)
    user, sys_, rss, wall = open(t).read().split()[-4:]
    return float(user) + float(sys_), int(rss) * 1024, float(wall)


def count(path):
    out = subprocess.run(["h5ls", path + "/bonds/neighbor"], capture_output=True, text=True).stdout
    bonds = int(out.split("{")[1].split("}")[0])
    out = subprocess.run(["h5ls", path + "/bonds/offsets"], capture_output=True, text=True).stdout
    return int(out.split("{")[1].split("}")[0]) - 1, bonds


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--new", required=True, help="bin directory of the build measured")
    ap.add_argument("--old", help="bin directory of the build compared with")
    ap.add_argument("--out", required=True)
    ap.add_argument("--sizes", default="2d:5e-4,2d:3.5e-4,2d:2.5e-4,3d:6.3e-4")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    builds = [("new", a.new)] + ([("old", a.old)] if a.old else [])
    print("| scene | nodes | bonds | build | CPU min / median (s) | peak RSS (GB) | wall min (s) |"
          " same bits |")
    print("|---|---|---|---|---|---|---|---|")
    for size in a.sizes.split(","):
        kind, h = size.split(":")
        scene = os.path.join(HERE, "plate2d.json" if kind == "2d" else "block3d.json")
        runs = {name: [] for name, _ in builds}
        for _ in range(a.repeat):
            for name, binary in builds:
                runs[name].append(pack(binary, scene, h, os.path.join(a.out, name + ".h5")))
        nodes, bonds = count(os.path.join(a.out, "new.h5"))
        same = ""
        if a.old:
            rc = subprocess.run(["h5diff", "--exclude-path", "/provenance",
                                 os.path.join(a.out, "old.h5"), os.path.join(a.out, "new.h5")],
                                capture_output=True).returncode
            same = "yes" if rc == 0 else "NO"
        for name, _ in builds:
            cpu = [r[0] for r in runs[name]]
            print("| %s h = %s | %d | %d | %s | %.1f / %.1f | %.2f | %.1f | %s |" % (
                kind, h, nodes, bonds, name, min(cpu), statistics.median(cpu),
                max(r[1] for r in runs[name]) / 1e9, min(r[2] for r in runs[name]), same))
        sys.stdout.flush()
        for name, _ in builds:
            os.remove(os.path.join(a.out, name + ".h5"))


if __name__ == "__main__":
    main()
