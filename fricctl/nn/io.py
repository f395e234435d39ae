"""The JSON file format of a :class:`~fricctl.nn.net.FrictionNet`: :func:`save_net`, :func:`load_net`.

A saved network is one JSON object::

    {"format": "fricctl.FrictionNet", "version": 1, "hidden": H,
     "w1": [[..], ..], "b1": [..], "w2": [..], "b2": ..,
     "input_offset": [Tm, omega], "input_scale": [Tm, omega],
     "output_offset": .., "output_scale": .., "envelope_low": [Tm, omega],
     "envelope_high": [Tm, omega],
     "units": {"inputs": ["N*m", "rad/s"], "output": "N*m", "side": "load"},
     "metadata": {...}}

Floats are written by :func:`json.dumps` (shortest round-trip repr), so a load
gives the same net bit for bit.  No pickle: a file is data, never code.
"""

from __future__ import annotations

import json
from pathlib import Path

from .. import _validate as v
from .net import FrictionNet

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "save_net", "load_net", "net_to_dict",
           "net_from_dict", "net_to_json", "net_from_json"]

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
        "units": {"inputs": ["N*m", "rad/s"], "output": "N*m", "side": "load"},
        "metadata": dict(net.metadata),
    }


def net_from_dict(data: dict) -> FrictionNet:
    """Inverse of :func:`net_to_dict`; a wrong format, version or key raises ``ValueError``."""
    if not isinstance(data, dict):
        raise ValueError(f"a saved FrictionNet is a JSON object, got {type(data).__name__}")
    if data.get("format") != FORMAT_NAME:
        raise ValueError(f"not a FrictionNet file: format is {data.get('format')!r}, "
                         f"expected {FORMAT_NAME!r}")
    if data.get("version") != FORMAT_VERSION:
        raise ValueError(f"unsupported FrictionNet format version {data.get('version')!r}; "
                         f"this fricctl reads version {FORMAT_VERSION}")
    expected = set(_FIELDS) | {"format", "version", "hidden", "units"}
    missing = sorted(expected - set(data))
    unknown = sorted(set(data) - expected)
    if missing:
        raise ValueError(f"FrictionNet file is missing key(s): {', '.join(missing)}")
    if unknown:
        raise ValueError(f"FrictionNet file has unknown key(s): {', '.join(unknown)}")
    net = FrictionNet(**{k: data[k] for k in _FIELDS})
    if data["hidden"] != net.hidden:
        raise ValueError(f"FrictionNet file says hidden={data['hidden']!r} but w1 has "
                         f"{net.hidden} rows")
    return net


def net_to_json(net: FrictionNet) -> str:
    """JSON text of ``net``; floats are written with round-trip precision."""
    return json.dumps(net_to_dict(net), indent=1, allow_nan=False)


def net_from_json(text: str) -> FrictionNet:
    """Parse :func:`net_to_json` output; malformed text raises ``ValueError``."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"malformed FrictionNet JSON: {exc}") from None
    return net_from_dict(data)


def save_net(net: FrictionNet, path) -> Path:
    """Write ``net`` as JSON to ``path`` (see :func:`net_to_json`); returns the path.

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
    path.write_text(net_to_json(net) + "\n", encoding="utf-8")
    return path


def load_net(path) -> FrictionNet:
    """Read a network written by :func:`save_net`.

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If the file is not valid JSON, not a FrictionNet, of another format
        version, or has missing, unknown or malformed entries.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a text file ({exc})") from None
    try:
        return net_from_json(text)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
