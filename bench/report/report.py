#!/usr/bin/python3
"""Charts and the HTML report of `penumbra compare` and `penumbra bench`.

    report.py compare DIR   reads DIR/metrics.json (what compare wrote), writes DIR/report.html and
                            DIR/speed_accuracy.png
    report.py bench DIR     reads DIR/bench.json (what bench wrote), writes DIR/report.html and
                            DIR/charts/*.png
    report.py tune DIR      reads DIR/tune.json (what tune wrote), writes DIR/tune.png and DIR/report.html
    report.py csv CSV DIR   reads the rows `compare --csv` appended (the bench/*.sh sweeps), writes
                            DIR/report.html and DIR/charts/*.png as for bench

Run with Debian's /usr/bin/python3 and python3-matplotlib (scripts/setup.sh installs it). The
C++ side (apps/report.cpp) calls this script; it is also usable by hand on an existing folder.
Everything the page shows comes from the JSON: nothing is measured here.
"""
import html
import json
import os
import sys

from charts import line_chart, speed_accuracy_chart

def esc(value):
    return html.escape(str(value), quote=True)


def fmt(value, digits=3, scale=1.0, suffix=""):
    if value is None:
        return "n/a"
    if isinstance(value, (int,)) and scale == 1.0:
        return f"{value:,}{suffix}"
    v = float(value) * scale
    if v != 0.0 and abs(v) < 10 ** -digits:
        return f"{v:.{digits - 1}e}{suffix}"
    return f"{v:.{digits}f}{suffix}"


def error_of(row, key):
    err = row.get("error")
    return None if not err else err.get(key)


STYLE = """
body { font-family: sans-serif; margin: 24px; color: #222; background: #fafafa; }
h1 { font-size: 22px; } h2 { font-size: 18px; margin-top: 28px; } h3 { font-size: 15px; }
table { border-collapse: collapse; margin: 8px 0 16px; font-size: 13px; background: white; }
th, td { border: 1px solid #bbb; padding: 3px 7px; text-align: right; }
th { background: #e8e8f0; } td.l, th.l { text-align: left; }
.strip { display: flex; flex-wrap: wrap; gap: 10px; }
figure { margin: 0; background: white; border: 1px solid #ccc; padding: 4px; }
figure img { width: 256px; height: auto; image-rendering: pixelated; display: block; }
figure.chart img { width: 640px; image-rendering: auto; }
figcaption { font-size: 12px; max-width: 256px; }
figure.chart figcaption { max-width: 640px; }
p.note { font-size: 13px; max-width: 60em; }
"""


def page(title, body):
    return (f"<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>{esc(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n<h1>{esc(title)}</h1>\n{body}\n</body></html>\n")


def figure(src, caption, chart=False):
    cls = " class='chart'" if chart else ""
    return f"<figure{cls}><img src='{esc(src)}' alt='{esc(caption)}'><figcaption>{esc(caption)}</figcaption></figure>"


def table(header, rows, left_columns=1):
    def cell(tag, i, v):
        cls = " class='l'" if i < left_columns else ""
        return f"<{tag}{cls}>{esc(v)}</{tag}>"
    out = ["<table><tr>" + "".join(cell("th", i, h) for i, h in enumerate(header)) + "</tr>"]
    for r in rows:
        out.append("<tr>" + "".join(cell("td", i, v) for i, v in enumerate(r)) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def context_note(ctx):
    parts = []
    for key in ("scene", "triangles", "resolution", "light", "light_size", "spp", "shadow_map_res", "tracer", "device",
                "driver", "machine"):
        if key in ctx and ctx[key] is not None:
            value = ctx[key]
            if key == "resolution" and isinstance(value, list):
                value = f"{value[0]}x{value[1]}"
            parts.append(f"{key.replace('_', ' ')}: {value}")
    return "<p class='note'>" + esc("; ".join(parts)) + "</p>"


def image_strip(dir_, entries):
    """entries: (relative path, caption); files that do not exist are left out."""
    figs = [figure(src, cap) for src, cap in entries if src and os.path.exists(os.path.join(dir_, src))]
    return "<div class='strip'>" + "".join(figs) + "</div>" if figs else ""


def method_images(prefix, method, label):
    """The images writeFrame/writeHeatmap leave for one method (prefix = folder part of the path)."""
    base = prefix + method
    return [(base + ".png", f"{label}: shaded"),
            (base + ".heatmap.png", f"{label}: |visibility - reference| (heatmap)"),
            (base + ".flip.png", f"{label}: FLIP vs reference"),
            (base + ".pip.png", f"{label}: pixels ray-traced (red)")]


def metrics_rows(rows, with_params=False):
    header = ["method"] + (["parameters"] if with_params else []) + [
        "time ms", "min", "max", "speed-up vs ref", "PIP %", "rays", "wrong %", "RMSE", "MAE", "max err",
        "FLIP (image)", "PIP miss", "trace bytes (sim.)", "temporal change", "vs ref's"]
    out = []
    for r in rows:
        out.append([r["method"]] + ([r.get("params_label", "")] if with_params else []) + [
            fmt(r["time_ms"], 1), fmt(r["time_min_ms"], 1), fmt(r["time_max_ms"], 1),
            fmt(r.get("speedup_vs_ref"), 2),
            fmt(r.get("pip_fraction"), 2, 100.0), fmt(r.get("rays_traced")),
            fmt(error_of(r, "wrong_pixel_fraction"), 4, 100.0), fmt(error_of(r, "rmse"), 4),
            fmt(error_of(r, "mae"), 4), fmt(error_of(r, "max"), 3), fmt(r.get("flip_mean"), 4),
            fmt(r.get("pip_miss_fraction"), 5),
            fmt(r.get("trace_bytes_simulated")),
            fmt(r.get("temporal_change"), 5), temporal_ratio(r)])
    return header, out


def temporal_ratio(row):
    """A method's frame-to-frame visibility change under the circling light over the reference's (1 = no extra flicker)."""
    mine, ref = row.get("temporal_change"), row.get("ref_temporal_change")
    return "n/a" if mine is None or not ref else fmt(float(mine) / float(ref), 2, suffix="x")


def chart_points(rows, error_key):
    pts = []
    for r in rows:
        pts.append({"label": r.get("label", r["method"]), "method": r["method"], "error": error_of(r, error_key),
                    "time": r["time_ms"], "tmin": r["time_min_ms"], "tmax": r["time_max_ms"]})
    return pts


# ---------------------------------------------------------------- compare

def stats_to_row(stats):
    """A row (the bench.json shape) from one method's stats in metrics.json."""
    t = stats.get("time_ms", {})
    trav = stats.get("traversal") or {}
    return {"method": stats["method"], "label": stats["method"], "tracer": stats.get("tracer"),
            "time_ms": t.get("total"), "time_min_ms": t.get("total_min", t.get("total")),
            "time_max_ms": t.get("total_max", t.get("total")), "pip_fraction": stats.get("pip_fraction"),
            "rays_traced": stats.get("rays_traced"), "node_visits_per_ray": trav.get("node_visits_per_ray"),
            "error": stats.get("error"), "pip_miss_fraction": stats.get("pip_miss_fraction"),
            "flip_mean": (stats.get("image_error") or {}).get("flip_mean"),
            "trace_bytes_simulated": stats.get("trace_bytes_simulated")}


def light_sections(dir_, methods, shown=8):
    """A frame of several lights: per method, each light's metrics against the reference's same light, and the
    images (lights/<method>.<i>.*) of the `shown` lights with the most wrong pixels."""
    out = []
    for s in methods:
        lights = s.get("lights") or []
        if len(lights) < 2:
            continue
        name = s["method"]
        out.append(f"<h3>{esc(name)}: per light</h3>")
        rows, wrong = [], []
        for i, l in enumerate(lights):
            err = l.get("error") or {}
            culled = any(n.startswith("culled") for n in l.get("notes", []))
            rows.append([str(i), "culled" if culled else (l.get("srt_path") or ""),
                         fmt(err.get("wrong_pixel_fraction"), 4, 100.0), fmt(err.get("rmse"), 4),
                         fmt(l.get("pip_fraction"), 2, 100.0), fmt(l.get("rays_traced")),
                         fmt(l.get("pip_miss_fraction"), 5), fmt(l.get("light_error_max"), 4),
                         fmt((l.get("time_ms") or {}).get("total"), 1)])
            if not culled:
                wrong.append((err.get("wrong_pixel_fraction") or 0.0, i))
        out.append(table(["light", "path", "wrong %", "RMSE", "PIP %", "rays", "PIP miss", "shade error", "time ms"],
                         rows, left_columns=2))
        for _, i in sorted(wrong, key=lambda w: (-w[0], w[1]))[:shown]:
            base = f"lights/{name}.{i}"
            out.append(image_strip(dir_, [(base + ".heatmap.png", f"light {i}: |visibility - reference|"),
                                          (base + ".pip.png", f"light {i}: pixels ray-traced (red)"),
                                          (base + ".visibility.png", f"light {i}: visibility")]))
    return out


def compare_report(dir_):
    with open(os.path.join(dir_, "metrics.json")) as f:
        metrics = json.load(f)
    ctx = metrics.get("scene", {})
    # One reference per term: ref for shadows, ao-embree / indirect-embree for methods ao and indirect.
    ref_stats = metrics.get("references") or [metrics["reference"]]
    refs = {s.get("term", "shadow"): stats_to_row(s) for s in ref_stats}
    ref = stats_to_row(metrics["reference"])
    rows = [stats_to_row(s) for s in metrics.get("methods", [])]
    for s, r in zip(metrics.get("methods", []), rows):
        own = refs.get(s.get("term", "shadow"), ref)
        if own["time_ms"] and r["time_ms"]:
            r["speedup_vs_ref"] = own["time_ms"] / r["time_ms"]
    chart = "speed_accuracy.png"
    speed_accuracy_chart(chart_points(rows, "rmse"), os.path.join(dir_, chart),
                         f"{ctx.get('scene', '')}: speed vs accuracy", "rmse", reference_ms=ref["time_ms"])
    body = [context_note(ctx), "<h2>Images</h2>"]
    for s in ref_stats:
        name = s["method"]
        body.append(image_strip(dir_, [(name + ".png", f"{name} (Embree): shaded"),
                                       (name + ".visibility.png", f"{name}: {s.get('term', 'shadow')} term")]))
    for r in rows:
        body.append(f"<h3>{esc(r['method'])}</h3>")
        body.append(image_strip(dir_, method_images("", r["method"], r["method"])))
    body += light_sections(dir_, metrics.get("methods", []))
    header, table_rows = metrics_rows([dict(refs[k], speedup_vs_ref=1.0) for k in refs] + rows)
    body += ["<h2>Metrics</h2>", table(header, table_rows),
             "<p class='note'>Errors are over covered pixels, of the visibility buffer (fraction of the light "
             "visible) against the Embree reference; wrong = |error| &gt; " +
             esc(ctx.get("wrong_pixel_threshold", "the threshold")) + "; FLIP: mean LDR-FLIP of the shaded image "
             "against the reference's (core/flip.h). Times are wall time per frame.</p>",
             "<h2>Speed vs accuracy</h2>",
             figure(chart, "one point per method (bar: min-max time); ringed, joined by the dashed staircase: the "
                           "Pareto frontier (no other method is both faster and more accurate)", chart=True)]
    with open(os.path.join(dir_, "report.html"), "w") as f:
        f.write(page(f"Penumbra compare: {ctx.get('scene', '')}", "\n".join(body)))


# ---------------------------------------------------------------- bench

def slug(text):
    return "".join(c if c.isalnum() else "_" for c in str(text)).strip("_")


def first_config(rows, method):
    """The row of `method` with its first parameter set (the sweep's first value on every axis)."""
    mine = [r for r in rows if r["method"] == method]
    return mine[0] if mine else None


def fig8_table(groups):
    header = ["scene", "triangles", "light size", "spp", "sm ms", "srt ms", "frt ms", "PIP %", "rays srt / frt",
              "frt/srt", "wrong % sm / srt"]
    out = []
    for g in groups:
        rows = g["rows"]
        sm, srt, frt = (first_config(rows, m) for m in ("sm", "srt", "frt"))
        if not (sm or srt or frt):
            continue
        ratio = frt["time_ms"] / srt["time_ms"] if srt and frt and srt["time_ms"] else None
        out.append([g["scene"], fmt(g["triangles"]), fmt(g["light_size"], 3), fmt((srt or frt or sm)["spp"]),
                    fmt(sm and sm["time_ms"], 1), fmt(srt and srt["time_ms"], 1), fmt(frt and frt["time_ms"], 1),
                    fmt(srt and srt.get("pip_fraction"), 2, 100.0),
                    f"{fmt(srt and srt.get('rays_traced'))} / {fmt(frt and frt.get('rays_traced'))}", fmt(ratio, 2),
                    f"{fmt(sm and error_of(sm, 'wrong_pixel_fraction'), 3, 100.0)} / "
                    f"{fmt(srt and error_of(srt, 'wrong_pixel_fraction'), 4, 100.0)}"])
    return header, out


def fig6_table(groups):
    header = ["scene", "triangles", "light size", "srt trace bytes (simulated)", "frt trace bytes (simulated)",
              "frt/srt", "srt bytes/ray", "frt bytes/ray"]
    out = []
    for g in groups:
        srt, frt = first_config(g["rows"], "srt"), first_config(g["rows"], "frt")
        if not (srt or frt):
            continue
        sb = srt and srt.get("trace_bytes_simulated")
        fb = frt and frt.get("trace_bytes_simulated")
        per = lambda b, r: b / r["rays_traced"] if b and r and r.get("rays_traced") else None  # noqa: E731
        out.append([g["scene"], fmt(g["triangles"]), fmt(g["light_size"], 3), fmt(sb), fmt(fb),
                    fmt(fb / sb if sb and fb else None, 2), fmt(per(sb, srt), 1), fmt(per(fb, frt), 1)])
    return header, out


def keul_table(groups):
    """Keul et al. 2017 Table 1 shape: per line-space parameter set, memory, build time, frame time, error."""
    header = ["scene", "triangles", "parameters", "memory MB", "build ms", "frame ms", "BVH frt ms", "RMSE"]
    out = []
    for g in groups:
        frt = first_config(g["rows"], "frt")
        for r in g["rows"]:
            if r["method"] != "ls":
                continue
            stats = r.get("stats", {})
            memory = sum(stats.get("memory_bytes", {}).values()) / 2 ** 20 if stats.get("memory_bytes") else None
            build = sum(stats.get("setup_ms", {}).values()) if stats.get("setup_ms") else None
            out.append([g["scene"], fmt(g["triangles"]), r.get("params_label", ""), fmt(memory, 1), fmt(build, 1),
                        fmt(r["time_ms"], 1), fmt(frt and frt["time_ms"], 1), fmt(error_of(r, "rmse"), 4)])
    return header, out


def bench_report(dir_):
    with open(os.path.join(dir_, "bench.json")) as f:
        bench = json.load(f)
    rows = bench["rows"]
    charts_dir = os.path.join(dir_, "charts")
    os.makedirs(charts_dir, exist_ok=True)
    # Groups: one scene at one light size (and reference spp): one reference, comparable errors.
    groups = []
    for r in rows:
        key = (r["scene"], r["light_size"], r.get("reference_spp"))
        g = next((g for g in groups if g["key"] == key), None)
        if g is None:
            g = {"key": key, "scene": r["scene"], "light_size": r["light_size"], "triangles": r["triangles"],
                 "rows": [], "ref": None, "images_dir": r.get("images_dir")}
            groups.append(g)
        if r["method"] == "ref":
            g["ref"] = r
        else:
            g["rows"].append(r)

    body = [context_note({"device": bench.get("device"), "driver": bench.get("driver"), "machine": bench.get("machine")}),
            "<p class='note'>" + esc(bench.get("description", "")) + "</p>"]

    body.append("<h2>Speed vs accuracy</h2>")
    for i, g in enumerate(groups):
        name = f"charts/speed_accuracy_{i:02d}_{slug(g['scene'])}.png"
        title = f"{g['scene']} ({g['triangles']:,} tris), light size {g['light_size']:g}"
        ref_ms = g["ref"]["time_ms"] if g["ref"] else None
        speed_accuracy_chart(chart_points(g["rows"], "rmse"), os.path.join(dir_, name), title, "rmse",
                             reference_ms=ref_ms)
        body.append(figure(name, title + ": one point per method and parameter set; ringed: the Pareto frontier",
                           chart=True))

    light_sizes = sorted({r["light_size"] for r in rows})
    triangles = sorted({r["triangles"] for r in rows})
    series_labels = list(dict.fromkeys(r["label"] for r in rows))
    method_of = {r["label"]: r["method"] for r in rows}
    if len(triangles) >= 2:
        body.append("<h2>Scalability: time vs triangles</h2>")
        for ls in light_sizes:
            series = {lab: (method_of[lab], [(r["triangles"], r["time_ms"]) for r in rows
                                              if r["label"] == lab and r["light_size"] == ls]) for lab in series_labels}
            name = f"charts/time_vs_triangles_light_{slug(ls)}.png"
            line_chart(series, os.path.join(dir_, name), f"time vs triangles, light size {ls:g}", "triangles",
                       "frame time, ms", logx=True, logy=True)
            body.append(figure(name, f"median frame time vs scene triangles at light size {ls:g}", chart=True))
    if len(light_sizes) >= 2:
        body.append("<h2>Scalability: time and PIP % vs light size</h2>")
        for scene in dict.fromkeys(r["scene"] for r in rows):
            mine = [r for r in rows if r["scene"] == scene]
            labels = list(dict.fromkeys(r["label"] for r in mine))
            series = {lab: (method_of[lab], [(r["light_size"], r["time_ms"]) for r in mine if r["label"] == lab])
                      for lab in labels}
            name = f"charts/time_vs_light_{slug(scene)}.png"
            line_chart(series, os.path.join(dir_, name), f"{scene}: time vs light size", "light size (scene radii)",
                       "frame time, ms")
            body.append(figure(name, f"{scene}: median frame time vs light size", chart=True))
            pip = {lab: (method_of[lab], [(r["light_size"], 100.0 * r["pip_fraction"]) for r in mine
                                          if r["label"] == lab and r.get("pip_fraction") is not None])
                   for lab in labels if any(r.get("pip_fraction") is not None for r in mine if r["label"] == lab)}
            if pip:
                name = f"charts/pip_vs_light_{slug(scene)}.png"
                line_chart(pip, os.path.join(dir_, name), f"{scene}: PIP % vs light size", "light size (scene radii)",
                           "pixels traced, % of covered")
                body.append(figure(name, f"{scene}: share of pixels ray-traced vs light size", chart=True))

    body.append("<h2>Paper-shaped tables</h2>")
    body.append("<h3>Lauterbach et al. 2009, Fig. 8 shape: sm / srt / frt times and PIP %</h3>")
    body.append("<p class='note'>Each method at its first parameter set of the sweep.</p>")
    body.append(table(*fig8_table(groups)))
    body.append("<h3>Lauterbach et al. 2009, Fig. 6 shape: simulated trace bandwidth, srt vs frt</h3>")
    body.append(table(*fig6_table(groups)))
    header, kt = keul_table(groups)
    if kt:
        body.append("<h3>Keul et al. 2017, Table 1 shape: line-space parameter sets</h3>")
        body.append(table(header, kt))

    body.append("<h2>Images</h2>")
    for g in groups:
        body.append(f"<h3>{esc(g['scene'])}, light size {g['light_size']:g}</h3>")
        entries = []
        if g["ref"] and g["ref"].get("images"):
            entries.append((g["ref"]["images"].get("image"), "ref (Embree)"))
        for r in g["rows"]:
            imgs = r.get("images") or {}
            for key, what in (("image", "shaded"), ("heatmap", "|error| heatmap"), ("flip", "FLIP"),
                              ("pip", "pixels traced (red)")):
                if imgs.get(key):
                    entries.append((imgs[key], f"{r['label']}: {what}"))
        body.append(image_strip(dir_, entries))

    body.append("<h2>All configurations</h2>")
    for g in groups:
        body.append(f"<h3>{esc(g['scene'])} ({g['triangles']:,} tris), light size {g['light_size']:g}</h3>")
        all_rows = ([dict(g["ref"], params_label=g["ref"].get("params_label", ""))] if g["ref"] else []) + g["rows"]
        header, trs = metrics_rows(all_rows, with_params=True)
        body.append(table(header, trs, left_columns=2))
    with open(os.path.join(dir_, "report.html"), "w") as f:
        f.write(page(bench.get("title", "Penumbra bench"), "\n".join(body)))


# ---------------------------------------------------------------- compare --csv (bench/*.sh)

def csv_report(csv_path, dir_):
    """The bench report from the CSV rows of `compare --csv`: one group per scene, light size and run."""
    import csv
    rows = []
    with open(csv_path) as f:
        for c in csv.DictReader(f):
            num = lambda k: float(c[k]) if c.get(k) not in (None, "") else None  # noqa: E731
            scene = c.get("scene_label") or c["scene"]
            extra = c.get("scaling") or ""
            rows.append({"scene": f"{scene} ({extra})" if extra else scene, "light_size": num("light_size") or 0.0,
                         "triangles": int(c["triangles"]), "method": c["method"],
                         "label": c["method"] + (f" ({c['tracer']})" if c.get("tracer") and c["method"] != "ref" else ""),
                         "tracer": c.get("tracer") or None, "spp": int(c["spp"]), "time_ms": num("total_ms"),
                         "time_min_ms": num("total_min_ms"), "time_max_ms": num("total_max_ms"),
                         "pip_fraction": num("pip_fraction"), "rays_traced": num("rays_traced"),
                         "node_visits_per_ray": num("node_visits_per_ray"),
                         "error": {"rmse": num("rmse"), "wrong_pixel_fraction": num("wrong_pixel_fraction")},
                         "pip_miss_fraction": num("pip_miss_fraction"), "device": c.get("device"),
                         "driver": c.get("driver")})
    os.makedirs(dir_, exist_ok=True)
    first = rows[0] if rows else {}
    bench = {"title": "Penumbra: " + os.path.basename(csv_path), "rows": rows, "device": first.get("device"),
             "driver": first.get("driver"),
             "description": f"From {csv_path} (rows of `penumbra compare --csv`); no images are kept by those sweeps."}
    with open(os.path.join(dir_, "bench.json"), "w") as f:
        json.dump(bench, f, indent=1)
    bench_report(dir_)


# ---------------------------------------------------------------- tune

def tune_report(dir_):
    with open(os.path.join(dir_, "tune.json")) as f:
        tune = json.load(f)
    key = tune["metric"]
    rows = tune["rows"]
    candidates = [r for r in rows if r["method"] != "ref"]
    pts = chart_points(candidates, key)
    chosen = None
    if tune.get("chosen"):
        chosen = next(p for p, r in zip(pts, candidates) if r["label"] == tune["chosen"]["label"])
    ref = next((r for r in rows if r["method"] == "ref"), None)
    title = (f"{tune['scene']}: cheapest under {key} <= {tune['max_error']:g}: "
             + (tune["chosen"]["label"] if tune.get("chosen") else "none"))
    speed_accuracy_chart(pts, os.path.join(dir_, "tune.png"), title, key, max_error=tune["max_error"], chosen=chosen,
                         reference_ms=ref["time_ms"] if ref else None)
    header, trs = metrics_rows(([ref] if ref else []) + candidates, with_params=True)
    body = [context_note({"scene": tune["scene"], "device": tune.get("device"), "driver": tune.get("driver"),
                          "machine": tune.get("machine")}),
            "<p class='note'>" + esc(tune.get("verdict", "")) + "</p>",
            figure("tune.png", "the candidates; left of the green line: within the bound; star: the choice", chart=True),
            table(header, trs, left_columns=2)]
    with open(os.path.join(dir_, "report.html"), "w") as f:
        f.write(page(f"Penumbra tune: {tune['scene']}", "\n".join(body)))


def main(argv):
    if argv[1:2] == ["csv"] and len(argv) == 4:
        csv_report(argv[2], argv[3])
        return 0
    if len(argv) != 3 or argv[1] not in ("compare", "bench", "tune"):
        sys.stderr.write("usage: report.py compare|bench|tune DIR | report.py csv CSV DIR\n")
        return 2
    {"compare": compare_report, "bench": bench_report, "tune": tune_report}[argv[1]](argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
