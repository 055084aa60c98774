#!/usr/bin/env python3
"""Error per second of vkgi's reference path tracer against Mitsuba 3 on the same scene and CPU.

Run through benches/mitsuba/run.sh (it installs Mitsuba from PyPI into its own virtual
environment; nothing here runs in CI). Steps:

1. `vkgi scene --write` exports the scene as OBJ + MTL + TOML; this script turns that into a
   Mitsuba scene: one mesh per material (face normals), a `diffuse` BSDF of the material's Kd,
   an `area` emitter of its Ke, a perspective camera of the same vertical field of view, a box
   pixel filter and the `path` integrator with unlimited depth.
2. A converged image: Mitsuba at --converged-spp (kept in the work folder for later runs).
3. Each renderer at --spp, --runs times with seeds 1..runs: Mitsuba `scalar_rgb` (the time of
   `mi.render`), `vkgi reference --tracer cpu` and `--tracer gpu` (the time vkgi records in the
   image's JSON sidecar: the trace, without process start-up and scene loading).
4. Each image's relMSE against the converged one, by `vkgi compare` (vkgi's own metric).

Efficiency is 1 / (relMSE x seconds): for an unbiased estimator relMSE falls as 1/samples, so
the product does not depend on the sample count. The ratio to Mitsuba's is printed per
renderer; above 1 means less error per second than Mitsuba.
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import time

import mitsuba as mi

mi.set_variant("scalar_rgb")


def read_written_scene(toml_path):
    """Camera, materials and faces of a scene written by `vkgi scene --write`."""
    folder = os.path.dirname(toml_path)
    text = open(toml_path).read()
    mesh = re.search(r'mesh = "([^"]+)"', text).group(1)
    camera = {
        key: [float(x) for x in re.search(key + r" = \[([^\]]+)\]", text).group(1).split(",")]
        for key in ("position", "target", "up")
    }
    camera["fov"] = float(re.search(r"fov = ([0-9.]+)", text).group(1))
    obj_path = os.path.join(folder, mesh)
    obj_lines = open(obj_path).read().splitlines(keepends=True)
    mtl = next(line.split()[1] for line in obj_lines if line.startswith("mtllib "))
    materials, current = {}, None
    for line in open(os.path.join(folder, mtl)):
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "newmtl":
            current = fields[1]
            materials[current] = {"Kd": [0.0] * 3, "Ke": [0.0] * 3}
        elif fields[0] in ("Kd", "Ke"):
            materials[current][fields[0]] = [float(x) for x in fields[1:4]]
        elif fields[0] == "map_Kd" or (fields[0] == "Ks" and any(float(x) > 0 for x in fields[1:4])):
            raise SystemExit(f"{toml_path}: {fields[0]} is not translated (diffuse scenes only)")
    vertices, faces, current = [], {}, None
    for line in obj_lines:
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "v":
            vertices.append(line)
        elif fields[0] == "usemtl":
            current = fields[1]
        elif fields[0] == "f":
            # Positions only: Mitsuba shades with face normals, as vkgi does without vertex normals.
            corners = [f.split("/")[0] for f in fields[1:]]
            faces.setdefault(current, []).append("f " + " ".join(corners) + "\n")
    return camera, materials, vertices, faces


def mitsuba_scene(toml_path, work, width, height):
    camera, materials, vertices, faces = read_written_scene(toml_path)
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": -1},
        "sensor": {
            "type": "perspective",
            "fov": camera["fov"],
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f.look_at(
                origin=camera["position"], target=camera["target"], up=camera["up"]
            ),
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
            "sampler": {"type": "independent"},
        },
    }
    for name, material_faces in faces.items():
        path = os.path.join(work, f"mesh-{name}.obj")
        with open(path, "w") as out:
            out.writelines(vertices)
            out.writelines(material_faces)
        shape = {
            "type": "obj",
            "filename": path,
            "face_normals": True,
            "bsdf": {
                "type": "diffuse",
                "reflectance": {"type": "rgb", "value": materials[name]["Kd"]},
            },
        }
        if max(materials[name]["Ke"]) > 0:
            shape["emitter"] = {
                "type": "area",
                "radiance": {"type": "rgb", "value": materials[name]["Ke"]},
            }
        scene[f"mesh-{name}"] = shape
    return mi.load_dict(scene)


def render_mitsuba(scene, spp, seed, out):
    start = time.perf_counter()
    image = mi.render(scene, spp=spp, seed=seed)
    seconds = time.perf_counter() - start
    mi.Bitmap(image).write(out)
    return seconds


def render_vkgi(vkgi, args, tracer, spp, seed, out):
    subprocess.run(
        [vkgi, "reference", "--scene", args.scene, "--size", args.size, "--bounces", "inf",
         "--spp", str(spp), "--seed", str(seed), "--tracer", tracer, "--out", out],
        check=True, stderr=subprocess.DEVNULL,
    )
    return json.load(open(out + ".json"))["seconds"]


def rel_mse(vkgi, image, converged, work):
    scores = os.path.join(work, "scores.json")
    subprocess.run([vkgi, "compare", image, converged, "--json", scores], check=True,
                   stdout=subprocess.DEVNULL)
    return json.load(open(scores))["rel_mse"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vkgi", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--scene", default="cornell-area")
    parser.add_argument("--size", default="256x256")
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--converged-spp", type=int, default=4096)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--tracers", default="cpu,gpu")
    args = parser.parse_args()
    width, height = (int(x) for x in args.size.lower().split("x"))
    os.makedirs(args.work, exist_ok=True)
    scene_dir = os.path.join(args.work, "scene")
    subprocess.run([args.vkgi, "scene", "--write", scene_dir, args.scene], check=True,
                   stderr=subprocess.DEVNULL)
    scene = mitsuba_scene(os.path.join(scene_dir, f"{args.scene}.toml"), args.work, width, height)

    converged = os.path.join(args.work, f"converged-{args.scene}-{args.size}-{args.converged_spp}.exr")
    if not os.path.exists(converged):
        print(f"converged image: Mitsuba at {args.converged_spp} spp ...", flush=True)
        seconds = render_mitsuba(scene, args.converged_spp, 1000, converged)
        print(f"  {seconds:.1f} s", flush=True)

    rows = {}
    for run in range(1, args.runs + 1):
        renderers = [("mitsuba scalar_rgb", None)] + [
            (f"vkgi --tracer {t}", t) for t in args.tracers.split(",") if t
        ]
        for name, tracer in renderers:
            out = os.path.join(args.work, f"{name.replace(' ', '_')}-{run}.exr")
            if tracer is None:
                seconds = render_mitsuba(scene, args.spp, run, out)
            else:
                seconds = render_vkgi(args.vkgi, args, tracer, args.spp, run, out)
            error = rel_mse(args.vkgi, out, converged, args.work)
            rows.setdefault(name, []).append((seconds, error))
            print(f"{name} run {run}: {seconds:.2f} s, relMSE {error:.3e}", flush=True)

    def medians(name):
        seconds = statistics.median(s for s, _ in rows[name])
        error = statistics.median(e for _, e in rows[name])
        return seconds, error

    base_seconds, base_error = medians("mitsuba scalar_rgb")
    print(f"\n{args.scene} {args.size}, {args.spp} spp, unlimited bounces, medians of {args.runs} runs;"
          f" relMSE against Mitsuba at {args.converged_spp} spp\n")
    print("| renderer | seconds | relMSE | relMSE x s | efficiency / Mitsuba |")
    print("|---|---|---|---|---|")
    for name in rows:
        seconds, error = medians(name)
        ratio = (base_error * base_seconds) / (error * seconds)
        print(f"| {name} | {seconds:.2f} | {error:.3e} | {error * seconds:.3e} | {ratio:.2f} |")


if __name__ == "__main__":
    main()
