#!/usr/bin/env python3
"""The render runs of a directory as one table (docs/render.md).

  render_table.py DIR [--markdown] [--time cpu|wall|device]

DIR holds one folder per run, ASSET-LEVEL/ with render.json, or a file
ASSET-LEVEL.refused saying why that run did not happen (a bake over
--max-bytes, ...), and optionally unsupported.tsv: METHOD<TAB>why for
methods the device could not trace (the hardware ones without
VK_EXT_opacity_micromap). Writes to
stdout a TSV (default): comment lines naming the device, driver and Vulkan
version of the runs, then one line per asset, level, tracer and method with
its counters, hit fraction, times (ms per frame, least of the frames) and
whether its check passed; refused runs and methods a run could not trace
get a line whose status says so. With --markdown: per asset and tracer, a
table of the fetches saved and of each method's time over the alpha
test's (the --time clock, default device where the runs have it, else
cpu), labelled with the device and driver. Standard library only.
"""
import json
import os
import sys

METHODS = ["alpha-test", "flat-4-state", "flat-2-state", "level-order-tree", "paper-tree",
           "hardware", "hardware-2-state"]
COLUMNS = ["asset", "level", "tracer", "method", "status", "candidates", "texture_fetches",
           "known", "unknown", "contradicted", "differing_pixels", "fetches_saved",
           "decided_without_texture", "any_hit_invocations", "hit_fraction", "cpu_ms",
           "wall_ms", "device_ms"]


# (method, why) of DIR/unsupported.tsv: methods no run could trace.
UNSUPPORTED = []


def runs(folder):
    """[(asset, level, render.json or None, why)] sorted by asset, level."""
    out = []
    for name in os.listdir(folder):
        base, _, ext = name.partition(".")
        asset, _, level = base.rpartition("-")
        if not level.isdigit():
            continue
        path = os.path.join(folder, name)
        if ext == "refused":
            out.append((asset, int(level), None, open(path).read().strip().splitlines()[-1]))
        elif os.path.isfile(os.path.join(path, "render.json")):
            out.append((asset, int(level), json.load(open(os.path.join(path, "render.json"))), ""))
    return sorted(out, key=lambda r: (r[0], r[1]))


def ms(seconds):
    return "" if seconds is None else "%.3f" % (1e3 * seconds)


def rows(found):
    for asset, level, j, why in found:
        if j is None:
            yield {"asset": asset, "level": level, "tracer": "-", "method": "-",
                   "status": "refused: " + why}
            continue
        failed = j["check"]["failures"]
        for m in j["methods"]:
            # render's labels: [LOOKUP ][TRACER ]METHOD, each part where
            # more than one was traced.
            lookup = m.get("lookup", "shader")
            labels = {"%s %s" % (m["tracer"], m["method"]), m["method"],
                      "%s %s %s" % (lookup, m["tracer"], m["method"]),
                      "%s %s" % (lookup, m["method"])}
            bad = [f for f in failed if f.split(":")[0] in labels]
            # The sampler lookup's entries as a tracer of their own.
            tracer = m["tracer"] if lookup == "shader" else "%s+%s" % (m["tracer"], lookup)
            yield {
                "asset": asset, "level": level, "tracer": tracer, "method": m["method"],
                "status": "failed" if bad else "ok",
                "candidates": m["candidates"], "texture_fetches": m["texture_fetches"],
                "known": m["known"], "unknown": m["unknown"], "contradicted": m["contradicted"],
                "differing_pixels": m.get("pixels_differing_from_must_equal") or 0,
                "fetches_saved": "%.4f" % m["texture_fetches_saved_fraction"],
                "decided_without_texture": "%.4f" % m["decided_without_texture_fraction"],
                "any_hit_invocations": m.get("any_hit_invocations", ""),
                "hit_fraction": "%.4f" % m.get("hit_fraction", 0.0),
                "cpu_ms": ms(m.get("cpu_seconds_per_frame")),
                "wall_ms": ms(m.get("wall_seconds_per_frame")),
                "device_ms": ms(m.get("device_seconds_per_frame")),
            }
        for method, why in UNSUPPORTED:
            yield {"asset": asset, "level": level, "tracer": "-", "method": method,
                   "status": "unsupported: " + why}


def header(found):
    devices = sorted({(j["device"], j["size"][0], j["size"][1]) for _, _, j, _ in found if j})
    lines = []
    for device, w, h in devices:
        lines.append("# device: " + device)
        lines.append("# size: %dx%d" % (w, h))
    for j in [j for _, _, j, _ in found if j][:1]:
        info = j.get("device_info", {})
        lines.append("# driver: %s %s, driver version %s, Vulkan %s" % (
            info.get("driver_name", "?"), info.get("driver_info", "?"),
            info.get("driver_version", "?"), info.get("vulkan_api_version", "?")))
        sampling = j.get("sampling", "?")
        # One line per lookup (render.json's sampling is per lookup).
        if isinstance(sampling, dict):
            for lookup in j.get("lookups", sorted(sampling)):
                lines.append("# sampling (%s lookup): %s" % (lookup, sampling.get(lookup, "?")))
        else:
            lines.append("# sampling: " + sampling)
        lines.append("# time: " + j.get("time", "?"))
    return lines


def tsv(found):
    out = header(found)
    out.append("\t".join(COLUMNS))
    for r in rows(found):
        out.append("\t".join(str(r.get(c, "")) for c in COLUMNS))
    return "\n".join(out) + "\n"


def markdown(found, clock):
    table = list(rows(found))
    if clock is None:
        clock = "device_ms" if any(r.get("device_ms") for r in table) else "cpu_ms"
    out = []
    j0 = next((j for _, _, j, _ in found if j), None)
    if j0:
        info = j0.get("device_info", {})
        out.append("Device: **%s**, driver %s %s (version %s), Vulkan %s; %dx%d primary rays; "
                   "time: `%s` per frame, least of the frames." % (
                       info.get("name", j0["device"]), info.get("driver_name", "?"),
                       info.get("driver_info", "?"), info.get("driver_version", "?"),
                       info.get("vulkan_api_version", "?"), j0["size"][0], j0["size"][1], clock))
        out.append("")
    for asset in sorted({r["asset"] for r in table}):
        refused = sorted({r["level"] for r in table
                          if r["asset"] == asset and r["status"].startswith("refused")})
        if refused and all(r["status"].startswith("refused") for r in table if r["asset"] == asset):
            why = next(r["status"] for r in table if r["asset"] == asset)
            out.append("**%s**: level%s %s refused (level %d: %s)" % (
                asset, "s" if len(refused) > 1 else "", ", ".join(map(str, refused)), refused[0],
                why.split("; nothing written")[0].replace("refused: micromap-index: ", "")))
            out.append("")
            continue
        for tracer in sorted({r["tracer"] for r in table if r["asset"] == asset and r["tracer"] != "-"}):
            out.append("**%s**, %s tracer" % (asset, tracer))
            out.append("")
            present = [m for m in METHODS if any(r["method"] == m and r["tracer"] in (tracer, "-")
                                                   and r["asset"] == asset for r in table)]
            head = ["level", "hit", "alpha ms", "fetches saved"] + \
                   ["%s / alpha" % m for m in present if m != "alpha-test"] + ["check"]
            out.append("| " + " | ".join(head) + " |")
            out.append("|" + "---|" * len(head))
            for level in sorted({r["level"] for r in table if r["asset"] == asset}):
                here = {r["method"]: r for r in table
                        if r["asset"] == asset and r["level"] == level and r["tracer"] in (tracer, "-")}
                refused = [r for r in here.values() if r["status"].startswith("refused")]
                if refused:
                    out.append("| %d | %s |" % (level, refused[0]["status"]))
                    continue
                alpha = here.get("alpha-test")
                if not alpha:
                    continue
                base = float(alpha[clock] or 0)
                cells = [str(level), "%.1f%%" % (100 * float(alpha["hit_fraction"])),
                         alpha[clock] or "-",
                         "%.1f%%" % (100 * float(here.get("flat-4-state", alpha)["fetches_saved"]))]
                for m in present:
                    if m == "alpha-test":
                        continue
                    r = here.get(m)
                    if r is None:
                        cells.append("-")
                    elif r["status"].startswith("unsupported"):
                        cells.append("unsupported")
                    elif base > 0 and r[clock]:
                        cells.append("%.2f" % (float(r[clock]) / base))
                    else:
                        cells.append("-")
                failed = [m for m, r in here.items() if r["status"] == "failed"]
                cells.append("failed: " + ", ".join(failed) if failed else "passed")
                out.append("| " + " | ".join(cells) + " |")
            out.append("")
    return "\n".join(out)


def main(argv):
    if not argv or argv[0].startswith("-"):
        sys.exit(__doc__)
    clock = None
    if "--time" in argv:
        clock = argv[argv.index("--time") + 1] + "_ms"
    unsupported = os.path.join(argv[0], "unsupported.tsv")
    if os.path.isfile(unsupported):
        UNSUPPORTED.extend(tuple(line.rstrip("\n").split("\t", 1))
                           for line in open(unsupported) if "\t" in line)
    found = runs(argv[0])
    sys.stdout.write(markdown(found, clock) if "--markdown" in argv else tsv(found))


if __name__ == "__main__":
    main(sys.argv[1:])
