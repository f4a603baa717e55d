#!/usr/bin/env python3
"""Reads what a run wrote (the .pvd and its VTU frames, the Exodus II file, history.csv and
history_units.csv) and checks them against each other (tests/cli/exodus_output.sh).

  check_outputs.py vtu DIR BASE NODES         node_id, reference_position, TimeValue of every frame
  check_outputs.py exodus DIR BASE NODES DX   the .e file against the .pvd, the frames and history.csv
  check_outputs.py same_exodus A.e B.e TOL    two Exodus files with equal content to a relative TOL
  check_outputs.py units DIR                  history_units.csv names a unit for each history.csv column

Exit status 0 when every check holds; otherwise the first failed check is printed and the
status is 1. Needs NumPy, and netCDF4 for the Exodus checks (Debian python3-numpy,
python3-netcdf4)."""
import base64
import csv
import os
import re
import struct
import sys
import zlib

import numpy as np

EPS = np.finfo(float).eps


def fail(message):
    print("check_outputs: " + message)
    sys.exit(1)


def decode_array(text, dtype, compressed):
    """A VTK binary DataArray: UInt64 headers, base64, zlib blocks when compressed."""
    text = "".join(text.split())
    if not compressed:
        raw = base64.b64decode(text)
        (count,) = struct.unpack("<Q", raw[:8])
        return np.frombuffer(raw[8 : 8 + count], dtype=dtype)
    first = base64.b64decode(text[:32])
    nblocks = struct.unpack("<Q", first[:8])[0]
    header_bytes = (3 + nblocks) * 8
    header_chars = 4 * ((header_bytes + 2) // 3)
    header = struct.unpack("<%dQ" % (3 + nblocks), base64.b64decode(text[:header_chars])[:header_bytes])
    data = base64.b64decode(text[header_chars:])
    out, at = [], 0
    for size in header[3:]:
        out.append(zlib.decompress(data[at : at + size]))
        at += size
    return np.frombuffer(b"".join(out), dtype=dtype)


def read_vtu(path):
    """Point data arrays (reshaped to n x ncomp), Points and the FieldData TimeValue."""
    text = open(path).read()
    compressed = "vtkZLibDataCompressor" in text
    arrays, time = {}, None
    m = re.search(r'Name="TimeValue"[^>]*format="ascii">([^<]+)<', text)
    if m:
        time = float(m.group(1))
    for m in re.finditer(r'<DataArray type="(\w+)" Name="([^"]+)"( NumberOfComponents="(\d+)")? format="binary">([^<]*)<', text):
        kind, name, ncomp, payload = m.group(1), m.group(2), int(m.group(4) or 1), m.group(5)
        dtype = {"Float64": "<f8", "Int32": "<i4", "Int64": "<i8", "UInt8": "u1"}[kind]
        values = decode_array(payload, dtype, compressed)
        arrays[name] = values.reshape(-1, ncomp) if ncomp > 1 else values
    return arrays, time


def read_pvd(directory, base):
    text = open(os.path.join(directory, base + ".pvd")).read()
    return [(float(t), f) for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', text)]


def read_frame(directory, file):
    """A frame: one .vtu, or the pieces of a .pvtu joined."""
    path = os.path.join(directory, file)
    if not file.endswith(".pvtu"):
        return read_vtu(path)
    pieces = re.findall(r'<Piece Source="([^"]+)"', open(path).read())
    joined, time = {}, None
    for piece in pieces:
        arrays, time = read_vtu(os.path.join(directory, piece))
        for name, values in arrays.items():
            joined.setdefault(name, []).append(values)
    return {name: np.concatenate(parts) for name, parts in joined.items()}, time


def read_history(directory):
    with open(os.path.join(directory, "history.csv")) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in row] for row in rows[1:]])


def check_vtu(directory, base, nodes):
    frames = read_pvd(directory, base)
    if not frames:
        fail("%s.pvd lists no frame" % base)
    for listed_time, file in frames:
        a, time = read_frame(directory, file)
        for name in ("node_id", "reference_position", "Points", "displacement"):
            if name not in a:
                fail("%s has no %s" % (file, name))
        ids = a["node_id"]
        if len(ids) != nodes or sorted(ids.tolist()) != list(range(1, nodes + 1)):
            fail("%s: node_id is not a numbering 1..%d of the %d nodes" % (file, nodes, len(ids)))
        # reference position = current position - displacement, to the round-off of one sum
        points, u, ref = a["Points"], a["displacement"], a["reference_position"]
        error = np.abs(points - u - ref).max()
        bound = 4 * EPS * max(np.abs(points).max(), np.abs(ref).max())
        if not error <= bound:
            fail("%s: |Points - displacement - reference_position| = %g > %g" % (file, error, bound))
        # the .pvd keeps 9 significant digits, TimeValue all 17
        if time is None:
            fail("%s has no FieldData TimeValue" % file)
        if abs(time - listed_time) > 1e-8 * max(abs(time), 1e-300) and not (time == 0 and listed_time == 0):
            fail("%s: TimeValue %.17g, the .pvd lists %.9g" % (file, time, listed_time))
    print("vtu: %d frames with node_id 1..%d, reference_position and TimeValue" % (len(frames), nodes))


def exodus_names(d, var):
    from netCDF4 import chartostring

    return [str(n) for n in chartostring(d[var][:])]


def by_id(frame_arrays, name):
    """A VTU field in node_id order (the order of the Exodus file's nodes)."""
    order = np.argsort(frame_arrays["node_id"])
    return frame_arrays[name][order]


def check_exodus(directory, base, nodes, dx):
    import netCDF4

    d = netCDF4.Dataset(os.path.join(directory, base + ".e"))
    names = exodus_names(d, "name_nod_var")
    expected = ["displacement_x", "displacement_y", "displacement_z", "velocity_x", "velocity_y", "velocity_z", "damage"]
    if names != expected:
        fail("node variables %s, expected %s" % (names, expected))
    if d.dimensions["num_nodes"].size != nodes or d.dimensions["num_elem"].size != nodes:
        fail("%d nodes and %d elements, expected %d of each" % (d.dimensions["num_nodes"].size, d.dimensions["num_elem"].size, nodes))
    if str(d["connect1"].elem_type).upper() != "SPHERE":
        fail("element type %s, expected SPHERE" % d["connect1"].elem_type)
    # grid nodes of a fill shape have the volume dx^3 (docs/deck.md, discretization)
    volume = np.asarray(d["attrib1"][:]).ravel()
    if np.abs(volume - dx**3).max() > 1e-12 * dx**3:
        fail("element attribute volume is not dx^3 = %g for every node" % dx**3)
    times = np.asarray(d["time_whole"][:])
    frames = read_pvd(directory, base)
    if len(times) != len(frames):
        fail("%d time steps, the .pvd lists %d frames" % (len(times), len(frames)))
    columns, history = read_history(directory)
    globals_ = exodus_names(d, "name_glo_var")
    if globals_ != columns:
        fail("global variables %s, history.csv columns %s" % (globals_, columns))
    glo = np.asarray(d["vals_glo_var"][:])
    coords = np.stack([np.asarray(d[c][:]) for c in ("coordx", "coordy", "coordz")], axis=1)
    for k, (listed_time, file) in enumerate(frames):
        a, vtu_time = read_frame(directory, file)
        if times[k] != vtu_time:
            fail("step %d: time %.17g, the frame's TimeValue %.17g" % (k + 1, times[k], vtu_time))
        if abs(times[k] - listed_time) > 1e-8 * max(abs(times[k]), 1e-300):
            fail("step %d: time %.17g, the .pvd lists %.9g" % (k + 1, times[k], listed_time))
        # the file's nodes are the frames' nodes in node_id order: the same numbers
        if not np.array_equal(coords, by_id(a, "reference_position")):
            fail("coordinates are not the frames' reference_position in node_id order")
        u = np.stack([np.asarray(d["vals_nod_var%d" % (c + 1)][k]) for c in range(3)], axis=1)
        if not np.array_equal(u, by_id(a, "displacement")):
            fail("step %d: displacement differs from frame %s" % (k + 1, file))
        damage = np.asarray(d["vals_nod_var7"][k])
        if not np.array_equal(damage, by_id(a, "damage")):
            fail("step %d: damage differs from frame %s" % (k + 1, file))
        # the global variables are the history.csv row of the frame's time (10 digits there)
        rows = np.nonzero(np.abs(history[:, 0] - times[k]) <= 1e-9 * max(abs(times[k]), 1e-300))[0]
        if len(rows) == 0:
            fail("history.csv has no row at the time %.9g of step %d" % (times[k], k + 1))
        row = history[rows[-1]]
        if not np.abs(glo[k] - row).max() <= 1e-9 * max(np.abs(row).max(), 1e-300) + 1e-300:  # NaN fails too
            fail("step %d: global variables %s, history.csv row %s" % (k + 1, glo[k], row))
    print("exodus: %d nodes, %d steps at the frames' times, %d node and %d global variables" %
          (nodes, len(times), len(names), len(globals_)))


def same_exodus(a, b, tol):
    import netCDF4

    da, db = netCDF4.Dataset(a), netCDF4.Dataset(b)
    skip = set()  # every variable is compared
    for name, var in da.variables.items():
        if name in skip:
            continue
        if name not in db.variables:
            fail("%s has %s, %s has not" % (a, name, b))
        x, y = np.asarray(var[:]), np.asarray(db[name][:])
        if x.shape != y.shape:
            fail("%s: shape %s in %s, %s in %s" % (name, x.shape, a, y.shape, b))
        if x.dtype.kind in "fi":
            scale = max(np.abs(x).max() if x.size else 0.0, 1e-300)
            if x.size and not np.abs(x - y).max() <= tol * scale:  # NaN fails too
                fail("%s differs: largest difference %g (scale %g)" % (name, np.abs(x - y).max(), scale))
        elif not np.array_equal(x, y):
            fail("%s differs" % name)
    print("same_exodus: %s and %s hold the same values" % (a, b))


def check_units(directory):
    with open(os.path.join(directory, "history.csv")) as f:
        header = next(csv.reader(f))
    with open(os.path.join(directory, "history_units.csv")) as f:
        rows = list(csv.reader(f))
    if len(rows) != 2 or rows[0] != header:
        fail("history_units.csv: expected the header of history.csv and one line of units")
    units = dict(zip(rows[0], rows[1]))
    if len(rows[1]) != len(header) or any(not u for u in rows[1]):
        fail("history_units.csv: a column without a unit: %s" % units)
    # units of docs/deck.md section 16
    known = {"time": "s", "step": "1", "kinetic_energy": "J", "strain_energy": "J", "external_work": "J",
             "energy_balance": "J", "broken_bond_fraction": "1"}
    for column, unit in units.items():
        want = known.get(column)
        if column.startswith("reaction_"):
            want = "N"
        elif column.startswith("momentum_"):
            want = "kg*m/s"
        elif column.startswith("displacement_"):
            want = "m"
        if want and unit != want:
            fail("history_units.csv: %s in %s, expected %s" % (column, unit, want))
    print("units: %d columns, each with a unit" % len(header))


if __name__ == "__main__":
    what = sys.argv[1]
    if what == "vtu":
        check_vtu(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    elif what == "exodus":
        check_exodus(sys.argv[2], sys.argv[3], int(sys.argv[4]), float(sys.argv[5]))
    elif what == "same_exodus":
        same_exodus(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    elif what == "units":
        check_units(sys.argv[2])
    else:
        fail("unknown check " + what)
