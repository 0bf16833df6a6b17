"""The cohort's configuration: which scans, with which gdm arguments.

Read by the Snakefile when it is parsed (no Snakemake import here, so the
module can be tested and reused on its own). It

- finds the gdm command (config `gdm`, else $GDM, else `gdm` on PATH, else the
  build tree's build/itk-module/apps/gdm),
- reads the flags this gdm knows from `gdm --help` (so a setting is only ever
  passed as a flag gdm has; a new gdm option needs no workflow edit),
- expands the config's scans (named entries and globs) into one entry per scan
  with its settings merged as defaults <- group <- scan,
- turns the settings into gdm's arguments,
- writes one parameter file per scan, only when its content changed (the scan
  job's input: a changed setting re-runs that scan and nothing else),
- estimates each scan's memory from its header (or its size on disk).
"""

import glob
import gzip
import json
import math
import os
import re
import shutil
import struct
import subprocess

# Settings with a name of their own in the config, and the gdm flag each maps
# to. Anything else goes through `options:` (name -> value becomes --name value).
NAMED_SETTINGS = {
    "threshold": "threshold",
    "polarity": "polarity",
    "seed": "seed",
    "seed_index": "seed-index",
    "gap": "gap",
    "gap_size": "gap",
    "face_budget": "max-faces",
    "mode": "mode",
    "smooth": "smooth",
    "roi": "roi",
    "series": "series",
    "allow_border": "allow-border",
}
# Settings of the workflow itself (not gdm flags).
WORKFLOW_SETTINGS = {"group", "path", "options", "threads", "mem_mb", "runtime_min"}
# Flags the workflow sets itself: refused in the config.
RESERVED_FLAGS = {"output", "o", "report", "quiet", "q", "threads", "help", "h", "version"}

MESH_FORMATS = ("ply", "vtk", "obj", "stl", "off")


class ConfigError(ValueError):
    """A mistake in the cohort's config, said with the scan and the setting."""


def find_gdm(configured, workflow_dir):
    """The gdm command to run: the config's, $GDM, PATH, then the build tree."""
    candidates = []
    if configured:
        candidates.append(str(configured))
    elif os.environ.get("GDM"):
        candidates.append(os.environ["GDM"])
    else:
        on_path = shutil.which("gdm")
        if on_path:
            candidates.append(on_path)
        candidates.append(os.path.join(workflow_dir, "..", "build", "itk-module", "apps", "gdm"))
    for c in candidates:
        found = shutil.which(c) if os.sep not in c else (c if os.access(c, os.X_OK) else None)
        if found:
            return os.path.abspath(found)
    raise ConfigError(
        "no gdm command found (tried %s): set `gdm:` in the config, $GDM, or build gdm "
        "(scripts/build.sh)" % ", ".join(candidates))


class Flags(dict):
    """{flag: takes a value}, with `primary`: {flag or alias: the option's own name}."""

    def __init__(self):
        super().__init__()
        self.primary = {}


def option_name(key):
    """A config key as a gdm flag name: `lod_face_area`, `--lod-face-area` -> `lod-face-area`."""
    return str(key).lstrip("-").replace("_", "-")


def gdm_flags(gdm):
    """{flag name: takes a value} from `gdm --help`, aliases included, and gdm's version."""
    text = subprocess.run([gdm, "--help"], capture_output=True, text=True, check=True).stdout
    # An option's block: "  --name VALUE  description" (two spaces in; the value,
    # upper case or choices a|b, one space after the name) and its description's
    # continuation lines.
    blocks = []
    for line in text.splitlines():
        m = re.match(r"^  --([a-z0-9][a-z0-9-]*)(?: ([A-Z][A-Za-z0-9_,.|-]*|[a-z0-9]+(?:\|[A-Za-z0-9,._-]+)+))?(?:\s|$)", line)
        if m:
            blocks.append([m.group(1), bool(m.group(2)), line])
        elif blocks and line.startswith("    "):
            blocks[-1][2] += " " + line.strip()
        elif not line.strip() or not line.startswith(" "):
            blocks.append([None, False, ""])
    flags = Flags()
    for name, takes_value, block in blocks:
        if name:
            flags[name] = takes_value
            flags.primary[name] = name
            for alias in re.findall(r"also (?:-[a-z], )?--([a-z0-9-]+)", block):
                flags.setdefault(alias, takes_value)
                flags.primary.setdefault(alias, name)
    version = subprocess.run([gdm, "--version"], capture_output=True, text=True).stdout.strip()
    return flags, version


def _scan_id(path):
    """A file's or folder's name without its image extensions, safe as a folder name."""
    name = os.path.basename(os.path.normpath(path))
    for ext in (".nii.gz", ".mha", ".mhd", ".nrrd", ".nhdr", ".nii", ".vtk", ".dcm"):
        if name.lower().endswith(ext):
            name = name[: -len(ext)]
            break
    return _safe(name)


def _safe(name):
    return re.sub(r"[^A-Za-z0-9._-]+", "_", str(name)).strip("._") or "scan"


def _merge(layers, primary):
    """Later layers win; `options` mappings are merged key by key, an option's
    aliases and spellings (lod, lod_face_area, lod-face-area) as one key."""
    out = {"options": {}}
    for layer in layers:
        for key, value in (layer or {}).items():
            if key == "options":
                for k, v in (value or {}).items():
                    name = option_name(k)
                    out["options"][primary.get(name, name)] = v
            else:
                out[key] = value
    return out


def _check_keys(where, settings):
    for key in settings:
        if key not in NAMED_SETTINGS and key not in WORKFLOW_SETTINGS:
            raise ConfigError(
                "%s: unknown setting %r (named settings: %s; any other gdm option goes under "
                "`options:`)" % (where, key, ", ".join(sorted(NAMED_SETTINGS))))
    if "options" in settings and not isinstance(settings["options"] or {}, dict):
        raise ConfigError("%s: `options` must be a mapping of gdm option name to value" % where)


def expand_scans(config, base_dir, flags=None):
    """[(scan id, absolute input path, merged settings)] in the config's order
    (`flags`, of gdm_flags: options merged by their gdm name, aliases included)."""
    primary = getattr(flags, "primary", {})
    defaults = config.get("defaults") or {}
    groups = config.get("groups") or {}
    _check_keys("defaults", defaults)
    for g, s in groups.items():
        _check_keys("group %s" % g, s or {})

    def settings_for(where, entry):
        entry = dict(entry or {})
        _check_keys(where, entry)
        group = entry.get("group")
        if group is not None and group not in groups:
            raise ConfigError("%s: group %r is not in `groups:` (%s)" % (where, group, ", ".join(groups) or "none"))
        return _merge([defaults, groups.get(group) if group is not None else None, entry], primary)

    def absolute(path):
        path = os.path.expanduser(str(path))
        return os.path.normpath(path if os.path.isabs(path) else os.path.join(base_dir, path))

    scans = []
    scans_cfg = config.get("scans") or {}
    if isinstance(scans_cfg, list):  # a list of paths, or of mappings with `path`
        scans_cfg = {(_scan_id(e) if isinstance(e, str) else _safe(e.get("name") or _scan_id(e["path"]))):
                     ({"path": e} if isinstance(e, str) else {k: v for k, v in e.items() if k != "name"})
                     for e in scans_cfg}
    for name, entry in scans_cfg.items():
        entry = {"path": entry} if isinstance(entry, str) else dict(entry or {})
        where = "scan %s" % name
        if "path" not in entry:
            raise ConfigError("%s: no `path`" % where)
        scans.append((_safe(name), absolute(entry["path"]), settings_for(where, entry)))
    for i, g in enumerate(config.get("globs") or []):
        g = {"pattern": g} if isinstance(g, str) else dict(g)
        pattern = g.pop("pattern", None)
        if not pattern:
            raise ConfigError("globs[%d]: no `pattern`" % i)
        prefix = g.pop("prefix", "")
        matches = sorted(glob.glob(absolute(pattern)))
        if not matches:
            print("gdm workflow: globs[%d] %r matches nothing" % (i, pattern))
        for path in matches:
            scans.append((_safe(prefix + _scan_id(path)), path, settings_for("glob %r" % pattern, g)))
    seen = {}
    for name, path, _ in scans:
        if name in seen:
            raise ConfigError("two scans are named %r (%s and %s): name them in `scans:` or give the glob a "
                              "`prefix:`" % (name, seen[name], path))
        seen[name] = path
    return scans


def _value_text(value):
    if isinstance(value, (list, tuple)):
        return ",".join(_value_text(v) for v in value)
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def gdm_arguments(name, settings, flags):
    """gdm's arguments for one scan's settings (without input, outputs, --threads)."""
    pairs = []
    for key, flag in NAMED_SETTINGS.items():
        if key in settings and settings[key] is not None:
            pairs.append((key, flag, settings[key]))
    for key, value in (settings.get("options") or {}).items():
        if value is None:
            continue
        pairs.append(("options." + str(key), option_name(key), value))
    args = []
    given = {}
    primary = getattr(flags, "primary", {})
    for where, flag, value in pairs:
        if primary.get(flag, flag) in given:
            raise ConfigError("scan %s: %s and %s both set --%s" % (name, given[primary.get(flag, flag)], where,
                                                                   primary.get(flag, flag)))
        given[primary.get(flag, flag)] = where
        if flag in RESERVED_FLAGS:
            raise ConfigError("scan %s: %s: the workflow sets --%s itself" % (name, where, flag))
        if flag not in flags:
            raise ConfigError("scan %s: %s: this gdm has no option --%s (see `gdm --help`)" % (name, where, flag))
        if flags[flag]:
            args += ["--" + flag, _value_text(value)]
        elif value is True or str(value).lower() in ("on", "yes", "true", "1"):
            args.append("--" + flag)  # a flag without a value: present or absent
        elif not (value is False or str(value).lower() in ("off", "no", "false", "0")):
            raise ConfigError("scan %s: %s: --%s takes no value; give true or false" % (name, where, flag))
    return args


def write_if_changed(path, text):
    """Writes `text` to `path` unless it holds it already (its time then stays)."""
    try:
        with open(path) as f:
            if f.read() == text:
                return False
    except FileNotFoundError:
        pass
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = "%s.tmp%d" % (path, os.getpid())
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
    return True


# --- memory estimate -------------------------------------------------------

def _header_voxels(path):
    """Voxel count from an image header, or None when it cannot be read cheaply."""
    lower = path.lower()
    try:
        text_headers = {(".mha", ".mhd"): r"^\s*DimSize\s*=\s*([0-9 ]+)$", (".nrrd", ".nhdr"): r"^sizes:\s*([0-9 ]+)$"}
        for suffixes, pattern in text_headers.items():
            if lower.endswith(suffixes):
                with open(path, "rb") as f:
                    head = f.read(65536).decode("latin-1")
                m = re.search(pattern, head, re.M)
                return math.prod(int(v) for v in m.group(1).split()) if m else None
        if lower.endswith((".nii", ".nii.gz")):
            opener = gzip.open if lower.endswith(".gz") else open
            with opener(path, "rb") as f:
                header = f.read(348)
            for order in "<>":
                (size,) = struct.unpack(order + "i", header[:4])
                if size == 348:
                    dims = struct.unpack(order + "8h", header[40:56])
                    return math.prod(max(1, d) for d in dims[1:1 + max(1, min(dims[0], 7))])
    except (OSError, ValueError, EOFError, struct.error):
        return None
    return None


def _disk_bytes(path):
    if os.path.isdir(path):
        return sum(os.path.getsize(os.path.join(d, f)) for d, _, files in os.walk(path) for f in files)
    return os.path.getsize(path) if os.path.exists(path) else 0


def estimate_mem_mb(path):
    """MiB to request for gdm on this scan: the float volume a few times over
    (input, smoothed copy, distance and work fields) plus the program's base.
    Voxels from the header when it can be read; otherwise from the size on
    disk (2 bytes a voxel, as CT; compressed files: 4 times their size)."""
    voxels = _header_voxels(path)
    if voxels is None:
        size = _disk_bytes(path)
        factor = 4 if path.lower().endswith((".gz", ".mha")) else 1
        voxels = size * factor // 2
    return int(256 + math.ceil(voxels * 4 * 5 / 2**20))
