"""FILE.xmf beside a trajectory file: the stick figure as a temporal collection of poly-lines, so ParaView
(its three XDMF readers), VisIt and meshio's TimeSeriesReader open the motion (File > Open FILE.xmf).

Every step's points are a whole HDF5 dataset of their own in a companion file, FILE.motion.h5 (/points/K,
(2n, 3), and /segments): a hyperslab of /motion/points is read by none of ParaView's Xdmf3 readers (0
points), makes the legacy reader print an error, and meshio reads no hyperslab; the trajectory file itself
is the run's output and is never written to. Each point also carries its position as a node vector,
"position": meshio's TimeSeriesReader takes the mesh from the first step and only attributes from the
others. Both files are written under temporary names and renamed (the .xmf last); a directory that
cannot be written is reported, not fatal (the page is still drawn)."""
import os
from xml.sax.saxutils import escape

import h5py

HEADER = '<?xml version="1.0" ?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n<Xdmf Version="3.0">\n<Domain>\n'
OWNER = "treedyn report"  # the companion's root attribute written_by: a file without it is never replaced


def data_item(h5, path, dimensions, number_type="Float"):
    return (f'<DataItem Dimensions="{dimensions}" NumberType="{number_type}" Precision="8" Format="HDF">'
            f'{h5}:{path}</DataItem>\n')


def step(h5, k, t, points, segments):
    here = data_item(h5, f"/points/{k}", f"{points} 3")
    return (f'<Grid Name="t{k}" GridType="Uniform">\n<Time Value="{t:.17g}"/>\n'
            f'<Topology TopologyType="Polyline" NumberOfElements="{segments}" NodesPerElement="2">\n'
            + data_item(h5, "/segments", f"{segments} 2", "Int") + '</Topology>\n<Geometry GeometryType="XYZ">\n'
            + here + '</Geometry>\n<Attribute Name="position" AttributeType="Vector" Center="Node">\n' + here
            + '</Attribute>\n</Grid>\n')


def xdmf_text(h5, times, points, segments):
    body = "".join(step(escape(h5), k, t, points, segments) for k, t in enumerate(times))
    return (HEADER + '<Grid Name="motion" GridType="Collection" CollectionType="Temporal">\n' + body
            + "</Grid>\n</Domain>\n</Xdmf>\n")


def write_companion(path, motion, source):
    with h5py.File(path, "w") as out:
        out.attrs["written_by"] = OWNER
        out.attrs["source"] = source
        out.attrs["description"] = ("the stick figure of the trajectory file `source` (its /motion/points, one "
                                    "dataset per output time, and /motion/segments), for FILE.xmf's readers")
        out["segments"] = motion["segments"][:]
        group = out.create_group("points")
        for k, rows in enumerate(motion["points"][:]):  # read whole: a row at a time inflates its chunk again
            group[str(k)] = rows


def foreign(path):
    """Why an existing file at the companion's path must not be replaced, or None."""
    if not os.path.lexists(path):
        return None
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("written_by") == OWNER:
                return None
    except OSError:
        pass
    return f"{path} exists and was not written by treedyn report"


def write_xdmf(f, file_name):
    """Returns the .xmf path written, or None with why."""
    if "motion/points" not in f:
        return None, "no /motion/points (an ensemble file, or one from an older treedyn)"
    stem = os.path.splitext(file_name)[0]
    target, companion = stem + ".xmf", stem + ".motion.h5"
    h5 = os.path.basename(companion)
    if ":" in h5:
        return None, f"the name {h5} has a ':', which XDMF takes as the file:dataset separator"
    why = foreign(companion)
    if why:
        return None, why
    _, points, _ = f["motion/points"].shape
    text = xdmf_text(h5, f["time"][:], points, f["motion/segments"].shape[0])
    temporaries = [f"{companion}.tmp-{os.getpid()}", f"{target}.tmp-{os.getpid()}"]
    writing = companion
    try:
        write_companion(temporaries[0], f["motion"], os.path.basename(file_name))
        writing = target
        with open(temporaries[1], "w", encoding="utf-8") as out:
            out.write(text)
        os.replace(temporaries[0], companion)
        try:
            os.replace(temporaries[1], target)
        except OSError:
            os.remove(companion)  # no companion without the .xmf that names it
            raise
    except OSError as e:
        for t in temporaries:
            if os.path.exists(t):
                os.remove(t)
        return None, f"cannot write {writing} ({e.strerror or e})"
    return target, None
