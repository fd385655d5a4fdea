"""A DEM trajectory (`[observe] snapshots = { every = ... }`) as ParaView reads it.

    check_trajectory.py AGGKIT WORK_DIR structure   the files checked with the standard library alone
    check_trajectory.py AGGKIT WORK_DIR vtk         the same files read by VTK's own XML readers

Runs a small DEM collapse with friction (so frames carry angular_velocity) and checks the collection
DIR/dem/trajectory.pvd and every frame it lists: the frame times are t = 0 and the output times `every`
apart, each frame has one point and one vertex cell per particle and the arrays of the final snapshot
(cluster, radius, velocity, angular_velocity) with the right lengths, frame 0 is the start (every speed 0.3,
as the scene says), the last frame is the final state (final.vtu, byte for byte), particles move between
frames, and the files stay within the disk estimate the scene reader checks the budget with.

The vtk mode installs Debian's python3-vtk9 if it is missing and it can (root, apt-get); when it cannot, it
prints why and exits 77 (CTest: skipped) — the structure mode still checks the same files.
"""
import base64
import math
import os
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

COUNT = 60
SCENE = f"""name = "trajectory-dem"
[particles]
dimension = 3
count = {COUNT}
radius = 1.0
mass = 1.0
boundary = "open"
initial = {{ cloud = "cube", volume_fraction = 0.05, speed = 0.3 }}
seed = 5
[time]
end = 4.0
every = 0.25
[[engine]]
name = "dem"
restitution = 0.5
contact_time = 0.05
friction = 0.5
gravity = {{ G = 1.0, method = "direct" }}
[observe]
series = ["clusters", "kinetic_energy"]
snapshots = {{ every = 1.0 }}
"""
FRAME_TIMES = [0.0, 1.0, 2.0, 3.0, 4.0]
ARRAYS = {"cluster": 1, "radius": 1, "velocity": 3, "angular_velocity": 3}
# validation/scene/scene_observe.cpp: frame_bytes_per_particle, the estimate the disk budget is checked with.
BYTES_PER_PARTICLE = (12 * 8 + 4 + 1) * 4.0 / 3.0
SIZES = {"Int32": ("i", 4), "Int64": ("q", 8), "UInt8": ("B", 1), "Float64": ("d", 8)}


def fail(message):
    print("FAILED: " + message)
    sys.exit(1)


def run_scene(aggkit, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    scene = os.path.join(work, "scene.toml")
    with open(scene, "w") as f:
        f.write(SCENE)
    out = os.path.join(work, "out")
    done = subprocess.run([aggkit, "run", scene, "--out", out, "--quiet", "--no-plot"], capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"aggkit run exited {done.returncode}: {done.stderr}")
    return os.path.join(out, "dem")


def collection(folder):
    root = ET.parse(os.path.join(folder, "trajectory.pvd")).getroot()
    if root.get("type") != "Collection":
        fail("trajectory.pvd is not a VTK collection")
    sets = root.find("Collection").findall("DataSet")
    return [(float(d.get("timestep")), d.get("file")) for d in sets]


def decode(array, components):
    """A DataArray in VTK's inline binary form: base64 of a UInt64 byte count, then the values."""
    raw = base64.b64decode(array.text.strip())
    (length,) = struct.unpack("<Q", raw[:8])
    code, size = SIZES[array.get("type")]
    if length != len(raw) - 8 or length % (size * components) != 0:
        fail(f"array {array.get('Name')}: header says {length} bytes, {len(raw) - 8} present")
    return struct.unpack("<%d%s" % (length // size, code), raw[8:])


def structure(folder):
    frames = collection(folder)
    if [t for t, _ in frames] != FRAME_TIMES:
        fail(f"frame times {[t for t, _ in frames]}, expected {FRAME_TIMES}")
    positions = []
    total_bytes = 0
    for t, name in frames:
        path = os.path.join(folder, name)
        total_bytes += os.path.getsize(path)
        piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")
        if int(piece.get("NumberOfPoints")) != COUNT or int(piece.get("NumberOfCells")) != COUNT:
            fail(f"{name}: {piece.get('NumberOfPoints')} points, {piece.get('NumberOfCells')} cells, expected {COUNT}")
        points = decode(piece.find("Points/DataArray"), 3)
        if len(points) != 3 * COUNT:
            fail(f"{name}: {len(points)} point coordinates")
        arrays = {a.get("Name"): a for a in piece.find("PointData").findall("DataArray")}
        if set(arrays) != set(ARRAYS):
            fail(f"{name}: arrays {sorted(arrays)}, expected {sorted(ARRAYS)}")
        values = {}
        for key, components in ARRAYS.items():
            values[key] = decode(arrays[key], components)
            if len(values[key]) != components * COUNT:
                fail(f"{name}: {key} has {len(values[key])} values, expected {components * COUNT}")
        if any(r != 1.0 for r in values["radius"]) or not all(0 <= c < COUNT for c in values["cluster"]):
            fail(f"{name}: radii or cluster labels out of place")
        if t == 0.0:
            v = values["velocity"]
            speeds = [math.sqrt(v[3 * i] ** 2 + v[3 * i + 1] ** 2 + v[3 * i + 2] ** 2) for i in range(COUNT)]
            if max(abs(s - 0.3) for s in speeds) > 1e-12:
                fail("frame 0 is not the start: its speeds are not the scene's 0.3")
        positions.append(points)
    for k in range(1, len(positions)):
        if positions[k] == positions[k - 1]:
            fail(f"frames {k - 1} and {k} hold the same positions")
    with open(os.path.join(folder, frames[-1][1]), "rb") as a, open(os.path.join(folder, "final.vtu"), "rb") as b:
        if a.read() != b.read():
            fail("the last frame differs from final.vtu")
    estimate = len(frames) * COUNT * BYTES_PER_PARTICLE + len(frames) * 2000  # the XML of a frame: under 2 kB
    if total_bytes > estimate:
        fail(f"{total_bytes} bytes of frames, above the estimate {estimate:.0f} the disk budget is checked with")
    print(f"structure: {len(frames)} frames of {COUNT} particles, {total_bytes} bytes (estimate {estimate:.0f})")
    return positions


def import_vtk():
    try:
        import vtk  # noqa: F401
        return vtk
    except ImportError:
        pass
    if os.geteuid() != 0 or shutil.which("apt-get") is None:
        return None
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    try:
        subprocess.run(["apt-get", "install", "-y", "--no-install-recommends", "python3-vtk9"], env=env,
                       capture_output=True, timeout=600, check=False)
    except subprocess.TimeoutExpired:
        return None
    try:
        import vtk  # noqa: F811
        return vtk
    except ImportError:
        return None


def read_with_vtk(folder, positions):
    vtk = import_vtk()
    if vtk is None:
        print("SKIPPED: VTK's reader: python3-vtk9 is not installed and could not be installed here "
              "(needs root, apt-get and the Debian archive); the structure test checks the same files")
        sys.exit(77)
    parser = vtk.vtkXMLDataParser()
    parser.SetFileName(os.path.join(folder, "trajectory.pvd"))
    if not parser.Parse():
        fail("VTK's XML parser cannot parse trajectory.pvd")
    sets = parser.GetRootElement().FindNestedElementWithName("Collection")
    frames = [(float(sets.GetNestedElement(i).GetAttribute("timestep")), sets.GetNestedElement(i).GetAttribute("file"))
              for i in range(sets.GetNumberOfNestedElements())]
    if [t for t, _ in frames] != FRAME_TIMES:
        fail(f"VTK reads frame times {[t for t, _ in frames]}")
    for k, (t, name) in enumerate(frames):
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(folder, name))
        reader.Update()
        grid = reader.GetOutput()
        if grid.GetNumberOfPoints() != COUNT or grid.GetNumberOfCells() != COUNT:
            fail(f"VTK reads {grid.GetNumberOfPoints()} points, {grid.GetNumberOfCells()} cells in {name}")
        data = grid.GetPointData()
        for key, components in ARRAYS.items():
            array = data.GetArray(key)
            if array is None or array.GetNumberOfTuples() != COUNT or array.GetNumberOfComponents() != components:
                fail(f"VTK reads no {key} of {COUNT} x {components} in {name}")
        read = [c for i in range(COUNT) for c in grid.GetPoint(i)]
        if read != list(positions[k]):
            fail(f"VTK reads other positions in {name} than the file holds")
    print(f"vtk {vtk.vtkVersion.GetVTKVersion()}: {len(frames)} frames read, {COUNT} points each")


def main():
    aggkit, work, mode = sys.argv[1:4]
    folder = run_scene(aggkit, work)
    positions = structure(folder)
    if mode == "vtk":
        read_with_vtk(folder, positions)


if __name__ == "__main__":
    main()
