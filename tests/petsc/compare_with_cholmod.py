#!/usr/bin/env python3
"""Runs bin/tailor on a scene with "linear_solver": "petsc" under mpiexec and on the same scene
with CHOLMOD (the keys removed, one process), and compares what the verbs report
(docs/petsc.md). Exits non-zero with a message on the first difference.

  simulate:  report.json results (energy, max displacement, reaction force) to --rtol; of a
             dynamic scene, the last step's energies and the last frame's displacement and
             velocity (every vertex) to --rtol
  gradcheck: gradcheck.json J(z0) and the directional derivative to --rtol, both passed
  run:       report.json final objective and design values to --rtol

The PETSc run must print each "wrote ..." line once (rank 0 alone writes), and its
report["linear_solver"] must hold the MPI size and every --expect KEY=VALUE.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ElementTree


def fail(message):
    print("FAILED: " + message)
    sys.exit(1)


def run(command, allowed=(0,)):
    print("$ " + " ".join(command), flush=True)
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(done.stdout)
    if done.returncode not in allowed:
        fail("exit code %d from %s" % (done.returncode, command[0]))
    return done.stdout


def relative(a, b):
    a = a if isinstance(a, list) else [a]
    b = b if isinstance(b, list) else [b]
    diff = math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))
    scale = math.sqrt(sum(y * y for y in b))
    return diff / scale if scale > 0 else diff


def compare(what, petsc, cholmod, rtol):
    r = relative(petsc, cholmod)
    print("%-40s petsc %-28s cholmod %-28s relative %.2e" % (what, petsc, cholmod, r))
    if not r <= rtol:
        fail("%s differs by %.2e relative (tolerance %.1e)" % (what, r, rtol))


def frame_field(path, name):
    """The values of point field `name` of a .vtu frame (tailor writes ASCII, round-trip digits)."""
    for array in ElementTree.parse(path).getroot().iter("DataArray"):
        if array.get("Name") == name:
            return [float(word) for word in array.text.split()]
    fail("%s has no field %s" % (path, name))


def compare_dynamics(p, c, out_p, out_c, rtol):
    for report, which in ((p, "petsc"), (c, "cholmod")):
        if report["status"] != "completed":
            fail("simulate: the %s run did not complete: %s" % (which, report["message"]))
    if p["dynamics"]["steps_done"] != c["dynamics"]["steps_done"]:
        fail("simulate: %d steps on PETSc, %d on CHOLMOD" % (p["dynamics"]["steps_done"], c["dynamics"]["steps_done"]))
    for key in ("kinetic_energy", "potential_energy"):
        compare("simulate last step " + key, p["steps"][-1][key], c["steps"][-1][key], rtol)
    with open(os.path.join(out_c, "result.pvd")) as f:
        last = ElementTree.parse(f).getroot().findall(".//DataSet")[-1].get("file")
    for field in ("displacement", "velocity"):
        a = frame_field(os.path.join(out_p, last), field)
        b = frame_field(os.path.join(out_c, last), field)
        r = relative(a, b)
        print("%-40s %d values, relative %.2e" % ("simulate %s %s" % (last, field), len(a), r))
        if len(a) != len(b) or not r <= rtol:
            fail("simulate %s %s differs by %.2e relative (tolerance %.1e)" % (last, field, r, rtol))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--tailor", required=True)
    parser.add_argument("--mpiexec", required=True, help="mpiexec and its flags, one string")
    parser.add_argument("--ranks", type=int, required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--verbs", default="simulate,gradcheck,run")
    parser.add_argument("--petsc-args", default="", help="PETSc options for the command line")
    parser.add_argument("--expect", action="append", default=[], help="KEY=VALUE of report linear_solver")
    parser.add_argument("--rtol", type=float, default=1e-8)
    args = parser.parse_args()

    os.makedirs(args.work, exist_ok=True)
    with open(args.scene) as f:
        scene = json.load(f)
    cholmod_scene = json.loads(json.dumps(scene))
    for key in ("linear_solver", "petsc_options"):
        cholmod_scene.get("solver", {}).pop(key, None)
    cholmod_path = os.path.join(args.work, "cholmod.json")
    with open(cholmod_path, "w") as f:
        json.dump(cholmod_scene, f, indent=1)

    mpiexec = args.mpiexec.split() + ["-n", str(args.ranks)]
    expected = {"name": "petsc", "processes": args.ranks}
    for item in args.expect:
        key, value = item.split("=", 1)
        try:
            expected[key] = json.loads(value)
        except ValueError:
            expected[key] = value

    for verb in args.verbs.split(","):
        out_c = os.path.join(args.work, "cholmod_" + verb)
        out_p = os.path.join(args.work, "petsc_" + verb)
        # A run that stops at the optimizer's iteration limit exits 1 (not converged): the test
        # scenes stop after a few iterations on purpose, and the statuses are compared below.
        allowed = (0, 1) if verb == "run" else (0,)
        run([args.tailor, verb, cholmod_path, "--out", out_c], allowed)
        log = run(mpiexec + [args.tailor, verb, args.scene, "--out", out_p] + args.petsc_args.split(), allowed)
        wrote = [line for line in log.splitlines() if "wrote " in line]
        if len(wrote) != 1:
            fail("%s: expected one 'wrote' line (rank 0 only), got %d" % (verb, len(wrote)))
        name = "gradcheck.json" if verb == "gradcheck" else "report.json"
        with open(os.path.join(out_c, name)) as f:
            c = json.load(f)
        with open(os.path.join(out_p, name)) as f:
            p = json.load(f)
        solver = p.get("linear_solver", {})
        print(verb + ": linear_solver " + json.dumps(solver))
        for key, value in expected.items():
            if solver.get(key) != value:
                fail("%s: linear_solver.%s is %r, expected %r" % (verb, key, solver.get(key), value))
        last = solver.get("last_solve") or {}
        if not last.get("converged"):
            fail(verb + ": the last PETSc solve did not converge")
        if c.get("linear_solver") != {"name": "cholmod"}:
            fail(verb + ": the reference did not run on CHOLMOD")
        if verb == "simulate" and c.get("kind") == "dynamics":
            compare_dynamics(p, c, out_p, out_c, args.rtol)
        elif verb == "simulate":
            for key in ("energy", "max_displacement", "reaction_force_total"):
                compare("simulate " + key, p["results"][key], c["results"][key], args.rtol)
        elif verb == "gradcheck":
            if not (p["passed"] and c["passed"]):
                fail("gradcheck: the Taylor test did not pass (petsc %s, cholmod %s)" % (p["passed"], c["passed"]))
            print("gradcheck on %d ranks: rates %.3f / %.3f (first / second order)" % (args.ranks, p["rate0"], p["rate1"]))
            adjoint = p.get("adjoint_linear_solves")
            if scene.get("dynamics"):
                # The transient adjoint's backward solves: on PETSc, to their own tolerance.
                if not adjoint or adjoint["solves"] != scene["dynamics"]["steps"]:
                    fail("gradcheck: expected one adjoint solve per step on PETSc, got %r" % adjoint)
                if not adjoint["last_relative_residual"] <= adjoint["relative_tolerance"]:
                    fail("gradcheck: the last adjoint solve missed its tolerance: %r" % adjoint)
                print("gradcheck adjoint: %d solves, %d iterations, tolerance %.0e, last residual %.2e"
                      % (adjoint["solves"], adjoint["iterations"], adjoint["relative_tolerance"],
                         adjoint["last_relative_residual"]))
            for key in ("value", "directional_derivative"):
                compare("gradcheck " + key, p[key], c[key], args.rtol)
        elif verb == "run":
            if p["status"] != c["status"] or p["status"] not in ("converged", "max_iterations"):
                fail("run: status %s on PETSc, %s on CHOLMOD" % (p["status"], c["status"]))
            if p["iterations"] != c["iterations"]:
                fail("run: %d optimizer iterations on PETSc, %d on CHOLMOD" % (p["iterations"], c["iterations"]))
            compare("run objective.final", p["objective"]["final"], c["objective"]["final"], args.rtol)
            compare("run design.values", p["design"]["values"], c["design"]["values"], args.rtol)
        else:
            fail("unknown verb " + verb)
    print("all agree to %.0e relative" % args.rtol)


if __name__ == "__main__":
    main()
