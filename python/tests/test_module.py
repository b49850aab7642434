# The module against independent references computed here: the command line's JSON and files,
# and float_body's replay and state hash. Each job runs the command line's own code, so where
# the same code runs the results are compared bit for bit.
import json
import os
import subprocess

import numpy as np
import pytest

from conftest import asset

MESH = asset("buoy.obj")


def same(module_value, cli_value):
    """Equal as the JSON says: arrays element by element, bit for bit."""
    if isinstance(module_value, np.ndarray):
        np.testing.assert_array_equal(module_value, np.asarray(cli_value, dtype=float))
    elif isinstance(module_value, dict):
        assert module_value.keys() == cli_value.keys()
        for key in module_value:
            same(module_value[key], cli_value[key])
    else:
        assert module_value == cli_value


def cli_error(done):
    """The message of the command line's last "error: " line."""
    assert done.returncode != 0
    lines = [line for line in done.stderr.splitlines() if line.startswith("error: ")]
    assert lines, done.stderr
    return lines[-1][len("error: "):]


def test_validate_gives_the_cli_facts(plimsoll, cli):
    same(plimsoll.validate(MESH), json.loads(cli("validate", MESH, "--json").stdout))


def test_a_unit_is_taken_as_the_command_lines_unit(plimsoll, cli):
    # A name and its number give the command line's --unit result.
    for unit in ("cm", "0.01"):
        same(plimsoll.validate(MESH, unit="cm"),
             json.loads(cli("validate", MESH, "--unit", unit, "--json").stdout))
    same(plimsoll.validate(MESH, unit=0.01), plimsoll.validate(MESH, unit="cm"))
    for bad in ("furlong", -1.0, 0.0, float("nan")):
        with pytest.raises(plimsoll.Error) as raised:
            plimsoll.validate(MESH, unit=bad)
        assert raised.value.kind == "invalid-argument"


def test_mesh_bake_massprops_round_trip(plimsoll, cli):
    reference = json.loads(cli("massprops", MESH, "--size", 64, "--density", 600, "--json").stdout)
    same(plimsoll.massprops(MESH, size=64, density=600), reference)
    exact = json.loads(cli("massprops", MESH, "--exact", "--density", 600, "--json").stdout)
    same(plimsoll.massprops(MESH, exact=True, density=600), exact)

    baked = plimsoll.bake(MESH, size=64)
    assert len(baked["texel_index"]) == reference["texel_samples"]
    assert len(np.unique(baked["texel_index"])) == reference["covered_texels"]
    assert baked["closure_error"] == reference["closure_error"]
    # The divergence theorem over the sample list, here in NumPy (one point per entry, so
    # first order: within 1e-3 of the command line's volume from the same bake, which
    # integrates each entry to higher order, and within 3e-3 of the exact one).
    p, a = baked["position"], baked["area_vector"]
    c = (p * baked["area"][:, None]).sum(axis=0) / baked["area"].sum()
    volume = np.einsum("ij,ij->", p - c, a) / 3
    assert volume == pytest.approx(reference["volume"], rel=1e-3)
    assert volume == pytest.approx(exact["volume"], rel=3e-3)  # 64^2: the CLI's is 1.6e-3 off
    assert reference["mass"] == pytest.approx(600 * reference["volume"], rel=1e-12)


def test_simulate_gives_the_cli_trajectory(plimsoll, cli, sample_projects, tmp_path):
    project = sample_projects / "buoy.plim.json"
    # Both runs read the radiation and atlas caches this first run writes.
    cli("simulate", project, "--seconds", 0)
    cli("simulate", project, "--seconds", 2, "--out", tmp_path / "t.json")
    cli("simulate", project, "--seconds", 2, "--out", tmp_path / "t.csv")
    run = plimsoll.simulate(str(project), seconds=2)

    rows = json.loads((tmp_path / "t.json").read_text())
    assert run["frames"] == len(rows) == 120
    for i, row in enumerate(rows):  # JSON holds every bit of each double
        assert row["time"] == run["time"][i]
        assert row["position"] == [run["x"][i], run["y"][i], run["z"][i]]
        assert row["orientation"] == [run["qw"][i], run["qx"][i], run["qy"][i], run["qz"][i]]
        assert row["velocity"] == [run["vx"][i], run["vy"][i], run["vz"][i]]
        assert row["angular_velocity"] == [run["wx"][i], run["wy"][i], run["wz"][i]]
        assert row["submerged_volume"] == run["submerged_volume"][i]
        assert row["buoyant_force"] == [run["fx"][i], run["fy"][i], run["fz"][i]]
        assert row["mass"] == run["mass"][i]
        assert row["center_of_mass"] == [run["com_x"][i], run["com_y"][i], run["com_z"][i]]
    # The CSV's columns, in its order and its 10 digits.
    lines = (tmp_path / "t.csv").read_text().splitlines()
    assert lines[0] == ",".join(["time", "body"] + run["columns"][1:])
    for i, line in enumerate(lines[1:]):
        values = ["%.10g" % v for v in run["table"][i]]
        assert line == ",".join(values[:1] + [run["body"][i]] + values[1:])


def grey_png(path, rows):
    """An 8-bit grey PNG of `rows` (lists of 0..255), written by hand: no imaging library."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(
            ">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + bytes(row) for row in rows)
    header = struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
                     chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def test_massprops_of_a_project_body_weighs_its_thickness_map(plimsoll, cli, tmp_path):
    # A shell painted 1 thick over half the UV square and 0.2 over the other half: the module,
    # the command line and the World (simulate's mass at the first frame) give one mass.
    grey_png(tmp_path / "thick.png", [[255] * 16 + [51] * 16 for _ in range(32)])
    body = {"name": "ball", "mesh": asset("sphere.obj"), "texture_size": 64, "radiation": False,
            "material": {"density": 300, "shell": {"surface_density": 10},
                         "thickness_map": "thick.png"}}
    project = tmp_path / "shell.plim.json"
    project.write_text(json.dumps({"schema_version": 1, "name": "t", "bodies": [body]}))
    reference = json.loads(cli("massprops", project, "--json").stdout)
    weighed = plimsoll.massprops(str(project))
    same(weighed, reference)
    assert weighed["mass"] == plimsoll.simulate(str(project), seconds=0.1)["mass"][0]
    del body["material"]["thickness_map"]
    project.write_text(json.dumps({"schema_version": 1, "name": "t", "bodies": [body]}))
    assert plimsoll.massprops(str(project), body="ball")["mass"] > weighed["mass"] + 1.0


def test_simulate_one_body_from_flags(plimsoll, cli, tmp_path):
    cli("simulate", "--mesh", MESH, "--density", 400, "--size", 32, "--no-radiation",
        "--position=0,0.3,0", "--seconds", 0.5, "--out", tmp_path / "t.json")
    rows = json.loads((tmp_path / "t.json").read_text())
    run = plimsoll.simulate(mesh=MESH, density=400, size=32, no_radiation=True,
                            position=(0, 0.3, 0), seconds=0.5)
    assert [r["position"][1] for r in rows] == list(run["y"])
    assert [r["submerged_volume"] for r in rows] == list(run["submerged_volume"])


def test_errors_are_exceptions_with_the_cli_kind_and_message(plimsoll, cli, tmp_path):
    missing = str(tmp_path / "missing.obj")
    with pytest.raises(plimsoll.Error) as caught:
        plimsoll.massprops(missing)
    assert caught.value.kind == "io"
    assert caught.value.message == cli_error(cli("massprops", missing, check=False))
    assert str(caught.value) == caught.value.message

    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with pytest.raises(plimsoll.Error) as caught:
        plimsoll.validate(str(broken))
    assert caught.value.kind == "format"
    assert caught.value.message == cli_error(cli("validate", broken, check=False))
    assert str(broken) in caught.value.message

    line = tmp_path / "line.obj"  # one triangle of no area: no solid can be made
    line.write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    report = plimsoll.validate(str(line))
    assert report["usable"] is False
    same(report, json.loads(cli("validate", line, "--json", check=False).stdout))
    with pytest.raises(plimsoll.Error) as caught:
        plimsoll.massprops(str(line), exact=True)
    assert caught.value.message == cli_error(cli("massprops", line, "--exact", check=False))

    with pytest.raises(plimsoll.Error) as caught:
        plimsoll.hydrostatics(str(tmp_path / "none.plim.json"))
    assert caught.value.kind == "io"
    with pytest.raises(plimsoll.Error) as caught:
        plimsoll.Bundle(str(tmp_path))
    assert caught.value.kind == "runtime" and caught.value.message


def test_hydrostatics_gives_the_cli_facts(plimsoll, cli, sample_projects):
    project = sample_projects / "box_half_draft.plim.json"
    reference = json.loads(cli("hydrostatics", project, "--exact", "--step", 30, "--json").stdout)
    result = plimsoll.hydrostatics(str(project), exact=True, step_deg=30)
    for out in (result, reference):
        out.pop("seconds")  # wall time
    same(result, reference)


def test_export_and_runtime_against_float_body(plimsoll, cli, float_body, sample_projects, tmp_path):
    project = str(sample_projects / "buoy.plim.json")
    entries = plimsoll.export(project, str(tmp_path / "module"))
    summary = json.loads(cli("export", project, "--out", tmp_path / "cli", "--quiet").stdout)
    assert len(entries) == len(summary["bodies"]) == 1
    assert entries[0]["status"] == "written"
    assert entries[0]["files"] == summary["bodies"][0]["files"]  # byte-identical bundles
    folder = entries[0]["folder"]

    csv = tmp_path / "float_body.csv"
    done = subprocess.run([float_body, folder, "3", "--csv", str(csv)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    expected_hash = done.stdout.split("state hash ")[1].strip()

    bundle = plimsoll.Bundle(folder)
    assert bundle.body == "buoy"
    simulation = plimsoll.Simulation(bundle)
    rows = simulation.run(3.0)
    assert f"{simulation.state_hash:016x}" == expected_hash
    lines = csv.read_text().splitlines()[1:]
    assert len(lines) == len(rows) == 180
    for line, row in zip(lines, rows):
        values = ["%.10g" % v for v in row]
        assert line == ",".join(values[:1] + [bundle.body] + values[1:])

    # A snapshot restored into a fresh simulation continues bit for bit.
    again = plimsoll.Simulation(bundle)
    again.run(1.0)
    saved = again.save()
    later = again.run(0.5)
    restored = plimsoll.Simulation(bundle)
    restored.restore(saved)
    np.testing.assert_array_equal(restored.run(0.5), later)
    assert restored.state_hash == again.state_hash

    # Instances: one body stepped by the runtime's own integrator, saved and restored.
    first, second = plimsoll.Instance(bundle), plimsoll.Instance(bundle)
    state = ((0.0, 0.2, 0.0), (1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    for step in range(120):
        state = first.step(*state, time=step / 240, dt=1 / 240)
    second.restore(first.save())
    assert second.state_hash == first.state_hash
    a = b = state
    for step in range(120, 240):
        a = first.step(*a, time=step / 240, dt=1 / 240)
        b = second.step(*b, time=step / 240, dt=1 / 240)
    assert a == b and first.state_hash == second.state_hash
    # The body settles: its weight is what the water carries.
    load = first.water_load(a[0], a[1], velocity=a[2], angular_velocity=a[3])
    weight = bundle.mass["mass"] * bundle.default_fluid["gravity"]
    assert load["forces"]["force"][1] == pytest.approx(weight, rel=0.05)
