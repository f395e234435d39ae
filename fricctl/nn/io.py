"""The JSON file format of a :class:`~fricctl.nn.net.FrictionNet`: :func:`save_net`, :func:`load_net`.

A saved network is one JSON object::

    {"format": "fricctl.FrictionNet", "version": 1, "hidden": H,
     "w1": [[..], ..], "b1": [..], "w2": [..], "b2": ..,
     "input_offset": [Tm, omega], "input_scale": [Tm, omega],
     "output_offset": .., "output_scale": .., "envelope_low": [Tm, omega],
     "envelope_high": [Tm, omega],
     "units": {"inputs": ["N*m", "rad/s"], "output": "N*m", "side": "load"},
     "metadata": {...}}

``units`` is the entry of the axis the net was trained on (``metadata["units"]``, see
:attr:`FrictionNet.units`): ``["N", "m/s"]`` and ``"N"`` on a linear axis.

Floats are written by :func:`json.dumps` (shortest round-trip repr), so a load
gives the same net bit for bit.  No pickle: a file is data, never code.

Reading is as strict as the model file's (:mod:`fricctl.plant.model`), through the
same reader (:func:`fricctl._validate.strict_json`): duplicate keys, NaN/Infinity,
nesting deeper than :data:`MAX_DEPTH`, a weight that is a string or a boolean, a
number beyond double precision, a ``version`` that is not the integer 1, an unknown
key or ``units`` entry raise :class:`ValueError` naming the key.
"""

from __future__ import annotations

import json
from pathlib import Path

from .. import _validate as v
from .._atomic import write_text
from ..units import UNITS as _UNITS
from .net import FrictionNet

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "MAX_DEPTH", "UNITS", "UNITS_OF", "save_net", "load_net",
           "net_to_dict", "net_from_dict", "net_to_json", "net_from_json"]

#: Deepest bracket nesting a network file may have (a saved net has 4).
MAX_DEPTH = 8
#: Value of the ``"format"`` key of a saved network.
FORMAT_NAME = "fricctl.FrictionNet"
#: Version of the JSON layout written by :func:`save_net`; :func:`load_net`
#: reads exactly this version.
FORMAT_VERSION = 1

_FIELDS = ("w1", "b1", "w2", "b2", "input_offset", "input_scale", "output_offset",
           "output_scale", "envelope_low", "envelope_high", "metadata")


def net_to_dict(net: FrictionNet) -> dict:
    """JSON-ready dict of ``net`` with the format name and version."""
    v.instance("net", net, FrictionNet)
    return {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "hidden": net.hidden,
        "w1": net.w1.tolist(),
        "b1": net.b1.tolist(),
        "w2": net.w2.tolist(),
        "b2": net.b2,
        "input_offset": net.input_offset.tolist(),
        "input_scale": net.input_scale.tolist(),
        "output_offset": net.output_offset,
        "output_scale": net.output_scale,
        "envelope_low": net.envelope_low.tolist(),
        "envelope_high": net.envelope_high.tolist(),
        "units": json.loads(json.dumps(UNITS_OF[net.units])),
        "metadata": dict(net.metadata),
    }


#: The ``units`` entry of a network file of each kind of axis (load side, SI).
UNITS_OF = {kind: {"inputs": [u.torque, u.velocity], "output": u.torque, "side": "load"}
            for kind, u in _UNITS.items()}
#: The ``units`` entry of a rotary joint's network (the paper's).
UNITS = UNITS_OF["rotary"]

#: Shapes of the numeric entries in the file (``None``: the number of hidden units).
_SHAPES = {"w1": (None, 2), "b1": ("H",), "w2": ("H",), "b2": (), "input_offset": (2,),
           "input_scale": (2,), "output_offset": (), "output_scale": (), "envelope_low": (2,),
           "envelope_high": (2,)}


def net_from_dict(data: dict) -> FrictionNet:
    """Inverse of :func:`net_to_dict`, strict: every problem is a ``ValueError`` naming the key.

    Refused: another format or version (``"version"`` must be the integer 1, not
    ``true`` or ``1.0``), a missing or unknown key, a weight that is not a JSON number
    (a string, a boolean, null) or lies beyond double precision, arrays of the wrong
    shape, ``hidden`` disagreeing with ``w1``, and a ``units`` entry other than one of
    :data:`UNITS_OF`, or of another axis than the metadata's ``units``.
    """
    if not isinstance(data, dict):
        raise ValueError(f"a saved FrictionNet is a JSON object, got {type(data).__name__}")
    fmt = data.get("format")
    if not (isinstance(fmt, str) and fmt == FORMAT_NAME):
        raise ValueError(f"format: not a FrictionNet file ({fmt!r}, expected {FORMAT_NAME!r})")
    version = data.get("version")
    if type(version) is not int or version != FORMAT_VERSION:
        raise ValueError(f"version: unsupported FrictionNet format version {version!r}; "
                         f"this fricctl reads version {FORMAT_VERSION} (an integer)")
    expected = set(_FIELDS) | {"format", "version", "hidden", "units"}
    missing = sorted(expected - set(data))
    unknown = sorted(set(data) - expected)
    if missing:
        raise ValueError(f"FrictionNet file is missing key(s): {', '.join(missing)}")
    if unknown:
        raise ValueError(f"FrictionNet file has unknown key(s): {', '.join(unknown)}")
    kind = next((k for k, u in UNITS_OF.items() if data["units"] == u), None)
    if kind is None or not isinstance(data["units"], dict):
        raise ValueError(f"units: a FrictionNet file has units {json.dumps(UNITS)} (rotary) or "
                         f"{json.dumps(UNITS_OF['linear'])} (linear; load side, SI), got "
                         f"{json.dumps(data['units'])[:120]}")
    meta = data["metadata"]
    trained = meta["units"] if isinstance(meta, dict) and "units" in meta else "rotary"
    # a linear net written before issue 26 has the rotary entry and "units": "linear" in its
    # metadata (which was right): read as linear; any other disagreement is refused
    if trained != kind and not (trained == "linear" and data["units"] == UNITS):
        raise ValueError(f"units: the file's units entry is a {kind} axis's, its metadata says "
                         f"the net was trained on a {trained!s:.20} axis")
    hidden = v.integer("hidden", data["hidden"], low=1)
    w1 = v.json_numbers("w1", data["w1"], shape=_SHAPES["w1"])
    if w1.shape[0] != hidden:
        raise ValueError(f"hidden: the file says hidden={hidden} but w1 has {w1.shape[0]} rows")
    values = {"w1": w1}
    for key, shape in _SHAPES.items():
        if key != "w1":
            x = v.json_numbers(key, data[key], shape=tuple(hidden if s == "H" else s
                                                           for s in shape))
            values[key] = float(x) if x.ndim == 0 else x
    v.instance("metadata", data["metadata"], dict, "a JSON object")
    return FrictionNet(**values, metadata=data["metadata"])


def net_to_json(net: FrictionNet) -> str:
    """JSON text of ``net``; floats are written with round-trip precision."""
    return json.dumps(net_to_dict(net), indent=1, allow_nan=False)


def net_from_json(text: str) -> FrictionNet:
    """Parse :func:`net_to_json` output; malformed text raises ``ValueError``."""
    try:
        # the one strict JSON reader of fricctl's files (fricctl._validate.strict_json):
        # nesting bounded (a net file is 4 deep: net > metadata > rng_state > state), so a
        # deeply nested file is a ValueError, not a RecursionError; duplicate keys, NaN and
        # integers of more than 1000 digits refused
        data = v.strict_json(text, max_depth=MAX_DEPTH)
    except ValueError as exc:
        raise ValueError(f"malformed FrictionNet JSON: {exc}") from None
    return net_from_dict(data)


def save_net(net: FrictionNet, path, *, overwrite: bool = True) -> Path:
    """Write ``net`` as JSON to ``path`` (see :func:`net_to_json`); returns the path.

    The file is written atomically (:mod:`fricctl._atomic`): complete, or not at all.
    ``overwrite=False`` refuses (:class:`FileExistsError`) a ``path`` that exists, also one
    another process creates while this one writes.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> net = FrictionNet(w1=[[1.0, 0.0]], b1=[0.0], w2=[1.0], b2=0.0,
    ...                   input_offset=[0, 0], input_scale=[1, 1], output_offset=0.0,
    ...                   output_scale=1.0, envelope_low=[-1, -1], envelope_high=[1, 1])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     back = load_net(save_net(net, pathlib.Path(d) / "net.json"))
    >>> back.hidden, float(back(0.5, 0.0)) == float(net(0.5, 0.0))
    (1, True)
    """
    v.instance("net", net, FrictionNet)
    path = Path(path)
    return write_text(path, net_to_json(net) + "\n", overwrite=v.flag("overwrite", overwrite))


def load_net(path) -> FrictionNet:
    """Read a network written by :func:`save_net`.

    Raises
    ------
    IsADirectoryError
        If ``path`` is a folder.
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file is not valid JSON, not a FrictionNet, of another format
        version, or has missing, unknown or malformed entries.
    """
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(21, "a folder, not a network file", str(path))
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a text file ({exc})") from None
    try:
        return net_from_json(text)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
