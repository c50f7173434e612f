"""FILE.xmf beside a trajectory file: the stick figure (/motion/points, /motion/segments) as a temporal
collection of poly-lines, every step's points a hyperslab of the HDF5 dataset, so ParaView or VisIt open
the motion (File > Open FILE.xmf, the XDMF reader). Written atomically; a directory that cannot be written
is reported, not fatal (the page is still drawn)."""
import os
from xml.sax.saxutils import escape

HEADER = '<?xml version="1.0" ?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n<Xdmf Version="3.0">\n<Domain>\n'


def step(h5, k, t, frames, points, segments):
    return (f'<Grid Name="t{k}" GridType="Uniform">\n<Time Value="{t:.17g}"/>\n'
            f'<Topology TopologyType="Polyline" NumberOfElements="{segments}" NodesPerElement="2">\n'
            f'<DataItem Dimensions="{segments} 2" NumberType="Int" Precision="8" Format="HDF">{h5}:/motion/segments'
            f'</DataItem>\n</Topology>\n<Geometry GeometryType="XYZ">\n'
            f'<DataItem ItemType="HyperSlab" Dimensions="1 {points} 3">\n'
            f'<DataItem Dimensions="3 3" Format="XML">{k} 0 0 1 1 1 1 {points} 3</DataItem>\n'
            f'<DataItem Dimensions="{frames} {points} 3" NumberType="Float" Precision="8" Format="HDF">'
            f'{h5}:/motion/points</DataItem>\n</DataItem>\n</Geometry>\n</Grid>\n')


def write_xdmf(f, file_name):
    """Returns the path written, or None with why."""
    if "motion/points" not in f:
        return None, "no /motion/points (an ensemble file, or one from an older treedyn)"
    frames, points, _ = f["motion/points"].shape
    segments = f["motion/segments"].shape[0]
    times = f["time"][:]
    h5 = os.path.basename(file_name)
    if ":" in h5:
        return None, f"its name {h5} has a ':', which XDMF takes as the file:dataset separator"
    h5 = escape(h5)
    body = "".join(step(h5, k, t, frames, points, segments) for k, t in enumerate(times))
    text = (HEADER + '<Grid Name="motion" GridType="Collection" CollectionType="Temporal">\n' + body
            + "</Grid>\n</Domain>\n</Xdmf>\n")
    target = os.path.splitext(file_name)[0] + ".xmf"
    temporary = f"{target}.tmp-{os.getpid()}"
    try:
        with open(temporary, "w", encoding="utf-8") as out:
            out.write(text)
        os.replace(temporary, target)
    except OSError as e:
        if os.path.exists(temporary):
            os.remove(temporary)
        return None, f"cannot write {target} ({e.strerror})"
    return target, None
