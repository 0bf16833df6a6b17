"""The cohort workflow (workflow/Snakefile) end to end, with Snakemake.

Six scans made here: the phantom as MHA, NIfTI and a DICOM series, the tooth
of ../shared/data (its row is left out, with a message, when absent), a
corrupt file and a seed outside the object. With --cores 2: a mesh, report
and picture for each of the four good scans, a failed row (gdm's exit code and
message) for each of the two bad ones, the table, the plot and the summary
page; a second run does nothing; a changed setting re-runs that scan and the
aggregate only; the SLURM profile's dry run lists the jobs with their
resources, and a run through stand-in sbatch/sacct/srun commands shows the
submissions themselves.

Environment: GDM_CLI (the gdm binary), GDM_SOURCE_DIR (the repository),
GDM_SHARED_DIR (../shared). Run: `ctest -R gdm_workflow` or
`GDM_CLI=build/itk-module/apps/gdm python3 -m pytest -q -rs workflow/test`.
"""

import csv
import json
import os
import re
import shutil
import stat
import subprocess
import sys
import time
import zlib

import pytest

SOURCE = os.environ.get("GDM_SOURCE_DIR") or os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SNAKEFILE = os.path.join(SOURCE, "workflow", "Snakefile")
PROFILE = os.path.join(SOURCE, "workflow", "profiles", "slurm")
GDM = os.path.abspath(os.environ.get("GDM_CLI") or os.path.join(SOURCE, "build", "itk-module", "apps", "gdm"))
SHARED = os.environ.get("GDM_SHARED_DIR") or os.path.join(SOURCE, "..", "shared")
TOOTH = os.path.join(SHARED, "data", "tooth", "tooth.mhd")


def _snakemake():
    """The snakemake command (Debian's /usr/bin/snakemake runs Debian's python3);
    $GDM_SNAKEMAKE names another (a path that does not exist: as if absent)."""
    if "GDM_SNAKEMAKE" in os.environ:
        chosen = os.environ["GDM_SNAKEMAKE"]
        return chosen if chosen and os.access(chosen, os.X_OK) else None
    return shutil.which("snakemake") or ("/usr/bin/snakemake" if os.path.exists("/usr/bin/snakemake") else None)


SNAKEMAKE = _snakemake()
if SNAKEMAKE is None:
    pytest.skip("snakemake is not installed (Debian: apt-get install snakemake; scripts/setup.sh installs it): "
                "the workflow test is skipped", allow_module_level=True)
for module, package in (("yaml", "python3-yaml"), ("numpy", "python3-numpy"), ("nibabel", "python3-nibabel"),
                        ("pydicom", "python3-pydicom"), ("vtk", "python3-vtk9")):
    try:
        __import__(module)
    except ImportError:
        pytest.skip("Python module %s is missing (Debian: %s; scripts/setup.sh installs it): the workflow test "
                    "is skipped" % (module, package), allow_module_level=True)
if not os.access(GDM, os.X_OK):
    pytest.skip("no gdm binary at %s (build it: cmake --build build --target gdm)" % GDM, allow_module_level=True)
if not os.environ.get("DISPLAY") and not shutil.which("Xvfb"):
    pytest.skip("no $DISPLAY and no Xvfb (Debian: xvfb) to render the pictures", allow_module_level=True)

import numpy as np  # noqa: E402


# --- inputs ------------------------------------------------------------------

def read_mha(path):
    """(voxels [z, y, x], spacing, origin) of a MetaImage with LOCAL, optionally zlib'd, data."""
    with open(path, "rb") as f:
        raw = f.read()
    header, pos = {}, 0
    while True:
        end = raw.index(b"\n", pos)
        key, _, value = raw[pos:end].decode("latin-1").partition("=")
        header[key.strip()] = value.strip()
        pos = end + 1
        if key.strip() == "ElementDataFile":
            break
    dims = [int(v) for v in header["DimSize"].split()]
    dtype = {"MET_SHORT": "<i2", "MET_UCHAR": "u1", "MET_FLOAT": "<f4"}[header["ElementType"]]
    data = raw[pos:]
    if header.get("CompressedData", "False") == "True":
        data = zlib.decompress(data)
    voxels = np.frombuffer(data, dtype=dtype).reshape(dims[::-1])
    spacing = [float(v) for v in header["ElementSpacing"].split()]
    origin = [float(v) for v in header.get("Offset", "0 0 0").split()]
    return voxels, spacing, origin


def write_nifti(path, voxels, spacing, origin):
    """The volume as NIfTI: nibabel's affine is RAS, gdm (ITK) reads LPS, so x and y are negated."""
    import nibabel as nib
    affine = np.diag([-spacing[0], -spacing[1], spacing[2], 1.0])
    affine[:3, 3] = [-origin[0], -origin[1], origin[2]]
    img = nib.Nifti1Image(np.ascontiguousarray(voxels.transpose(2, 1, 0)), affine)  # [i, j, k]
    img.set_qform(affine, code=1)
    img.set_sform(affine, code=1)
    nib.save(img, path)


def write_dicom_series(folder, voxels, spacing, origin):
    """One CT slice file per z, with positions, orientation, spacing and rescale."""
    import pydicom
    from pydicom.dataset import Dataset, FileMetaDataset
    from pydicom.uid import ExplicitVRLittleEndian, generate_uid
    os.makedirs(folder, exist_ok=True)
    ct = "1.2.840.10008.5.1.4.1.1.2"
    study, series, frame = generate_uid(), generate_uid(), generate_uid()
    nz, ny, nx = voxels.shape
    for k in range(nz):
        uid = generate_uid()
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = ct
        meta.MediaStorageSOPInstanceUID = uid
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        ds = Dataset()
        ds.file_meta = meta
        ds.is_little_endian, ds.is_implicit_VR = True, False
        ds.SOPClassUID, ds.SOPInstanceUID = ct, uid
        ds.StudyInstanceUID, ds.SeriesInstanceUID, ds.FrameOfReferenceUID = study, series, frame
        ds.Modality, ds.PatientName, ds.PatientID = "CT", "Phantom^Workflow", "gdm-workflow-test"
        ds.SeriesNumber, ds.InstanceNumber = 1, k + 1
        ds.ImagePositionPatient = [origin[0], origin[1], origin[2] + k * spacing[2]]
        ds.ImageOrientationPatient = [1, 0, 0, 0, 1, 0]
        ds.PixelSpacing = [spacing[1], spacing[0]]  # rows (y), columns (x)
        ds.SliceThickness = spacing[2]
        ds.Rows, ds.Columns = ny, nx
        ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
        ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
        ds.RescaleIntercept, ds.RescaleSlope = 0, 1
        ds.PixelData = np.ascontiguousarray(voxels[k].astype("<i2")).tobytes()
        pydicom.dcmwrite(os.path.join(folder, "slice-%03d.dcm" % (k + 1)), ds, write_like_original=False)


def write_config(path, work, changed=False):
    """The cohort: named scans, one group for the phantom's threshold, defaults."""
    lines = [
        "gdm: %s" % json.dumps(GDM),
        "results: results",
        "defaults:",
        "  face_budget: 200000",
        "  threads: 1",
        "groups:",
        "  phantom:",
        "    threshold: 400",
        "scans:",
        "  phantom_mha: {path: inputs/phantom.mha, group: phantom}",
        "  phantom_nifti: {path: inputs/phantom.nii.gz, group: phantom%s}" % (
            ", options: {lod-face-area: 6}" if changed else ""),
        "  phantom_dicom: {path: inputs/dicom, group: phantom}",
    ]
    if os.path.exists(TOOTH):
        lines.append("  tooth: {path: %s, threshold: 115, polarity: dark, seed_index: [50, 47, 95]}"
                     % json.dumps(TOOTH))
    lines += [
        "  corrupt: {path: inputs/corrupt.mha, group: phantom}",
        "  seed_outside: {path: inputs/phantom.mha, group: phantom, seed: [1, 1, 1]}",
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def snakemake(work, *args, profile=None, env=None):
    command = [SNAKEMAKE, "-s", SNAKEFILE, "--configfile", "config.yaml"] + list(args)
    if profile:
        command += ["--profile", profile]
    started = time.monotonic()
    run = subprocess.run(command, cwd=work, capture_output=True, text=True, env=env)
    seconds = time.monotonic() - started
    print("$ %s  (%.1f s, exit %d)" % (" ".join(command), seconds, run.returncode))
    return run, seconds


def job_counts(output):
    """{rule: jobs} of Snakemake's "Job stats" table."""
    counts = {}
    table = output.split("Job stats:", 1)[1] if "Job stats:" in output else ""
    for line in table.splitlines()[3:]:
        m = re.match(r"^(\w+)\s+(\d+)\s", line)
        if not m:
            break
        if m.group(1) != "total":
            counts[m.group(1)] = int(m.group(2))
    return counts


def rows(work):
    with open(os.path.join(work, "results", "cohort.csv")) as f:
        return {r["scan"]: r for r in csv.DictReader(f)}


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    work = str(tmp_path_factory.mktemp("cohort"))
    inputs = os.path.join(work, "inputs")
    os.makedirs(inputs)
    phantom = os.path.join(SOURCE, "data", "phantom.mha")
    shutil.copy(phantom, os.path.join(inputs, "phantom.mha"))
    voxels, spacing, origin = read_mha(phantom)
    write_nifti(os.path.join(inputs, "phantom.nii.gz"), voxels, spacing, origin)
    write_dicom_series(os.path.join(inputs, "dicom"), voxels, spacing, origin)
    with open(os.path.join(inputs, "corrupt.mha"), "w") as f:  # a header that lies about its data
        f.write("ObjectType = Image\nNDims = 3\nDimSize = 64 64 64\nElementType = MET_SHORT\n"
                "ElementDataFile = LOCAL\nnot the voxels")
    if not os.path.exists(TOOTH):
        print("NOTE: %s is absent: the tooth's row is left out (five scans, not six)" % TOOTH)
    write_config(os.path.join(work, "config.yaml"), work)
    return work


def test_first_run_makes_meshes_pictures_table_and_summary(work):
    run, seconds = snakemake(work, "--cores", "2")
    assert run.returncode == 0, run.stderr[-3000:]
    table = rows(work)
    good = ["phantom_mha", "phantom_nifti", "phantom_dicom"] + (["tooth"] if os.path.exists(TOOTH) else [])
    assert sorted(table) == sorted(good + ["corrupt", "seed_outside"])
    for name in good:
        r = table[name]
        assert r["status"] == "ok" and r["exit_code"] == "0", r
        assert r["valid"] == "True" and int(r["faces"]) > 500 and float(r["volume_mm3"]) > 0, r
        assert int(r["cycles"]) > 0 and float(r["area_mm2"]) > 0 and r["closed"] == "True", r
        folder = os.path.join(work, "results", "scans", name)
        for f in ("mesh.ply", "report.json", "status.json"):
            assert os.path.getsize(os.path.join(folder, f)) > 0, (name, f)
        with open(os.path.join(folder, "picture.png"), "rb") as f:
            png = f.read()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000, (name, len(png))
        with open(os.path.join(folder, "report.json")) as f:
            assert json.load(f)["mesh"]["faces"] == int(r["faces"])
    # The same phantom from three formats: the same mesh.
    volumes = [float(table[n]["volume_mm3"]) for n in ("phantom_mha", "phantom_nifti", "phantom_dicom")]
    assert max(volumes) - min(volumes) < 1e-3 * volumes[0], volumes
    assert len({table[n]["faces"] for n in ("phantom_mha", "phantom_nifti", "phantom_dicom")}) == 1

    bad = {"corrupt": ("3", "truncated"), "seed_outside": ("2", "not inside the object")}
    for name, (code, words) in bad.items():
        r = table[name]
        assert r["status"] == "failed" and r["exit_code"] == code and words in r["message"], r
        assert r["mesh"] == "" and r["picture"] == "", r
        assert not os.path.exists(os.path.join(work, "results", "scans", name, "mesh.ply"))

    with open(os.path.join(work, "results", "summary.html")) as f:
        page = f.read()
    for name in good:
        assert "scans/%s/picture.png" % name in page
    assert "not inside the object" in page and "truncated" in page and 'src="volumes.svg"' in page
    with open(os.path.join(work, "results", "volumes.svg")) as f:
        assert "<svg" in f.read(1000)

    print("first run, --cores 2: %.1f s for %d scans" % (seconds, len(table)))
    for name, r in table.items():
        print("  %-14s %-6s exit %-2s gdm %6s s, picture %6s s, scan job %6s s, %6s faces, %10s mm^3" % (
            name, r["status"], r["exit_code"], r["gdm_seconds"] or "-", r["render_seconds"] or "-",
            r["job_seconds"], r["faces"] or "-", r["volume_mm3"] or "-"))


def test_second_run_does_nothing(work):
    status = os.path.join(work, "results", "scans", "phantom_mha", "status.json")
    before = os.stat(status).st_mtime_ns
    dry, _ = snakemake(work, "-n", "--cores", "2")
    assert dry.returncode == 0, dry.stderr[-2000:]
    assert "Nothing to be done" in dry.stdout + dry.stderr, dry.stdout + dry.stderr
    run, _ = snakemake(work, "--cores", "2")
    assert run.returncode == 0 and "Nothing to be done" in run.stdout + run.stderr
    assert os.stat(status).st_mtime_ns == before


def test_changed_setting_reruns_that_scan_and_the_aggregate(work):
    folders = os.path.join(work, "results", "scans")
    before = {n: os.stat(os.path.join(folders, n, "status.json")).st_mtime_ns for n in os.listdir(folders)}
    faces_before = int(rows(work)["phantom_nifti"]["faces"])
    write_config(os.path.join(work, "config.yaml"), work, changed=True)
    dry, _ = snakemake(work, "-n", "--cores", "2")
    assert dry.returncode == 0, dry.stderr[-2000:]
    out = dry.stdout + dry.stderr
    assert job_counts(out) == {"scan": 1, "aggregate": 1, "all": 1}, out[-3000:]
    assert "wildcards: scan=phantom_nifti" in out and out.count("rule scan:") == 1
    run, _ = snakemake(work, "--cores", "2")
    assert run.returncode == 0, run.stderr[-2000:]
    after = {n: os.stat(os.path.join(folders, n, "status.json")).st_mtime_ns for n in os.listdir(folders)}
    assert [n for n in before if after[n] != before[n]] == ["phantom_nifti"]
    assert int(rows(work)["phantom_nifti"]["faces"]) > faces_before  # a finer level of detail
    again, _ = snakemake(work, "-n", "--cores", "2")
    assert "Nothing to be done" in again.stdout + again.stderr


def test_slurm_profile_dry_run_lists_the_jobs(work):
    dry, _ = snakemake(work, "-n", "--forceall", profile=PROFILE)
    out = dry.stdout + dry.stderr
    assert dry.returncode == 0, out[-3000:]
    n = len(rows(work))
    assert job_counts(out) == {"scan": n, "aggregate": 1, "all": 1}, out[-3000:]
    scans = re.findall(r"rule scan:\n(?:    .*\n)*?    wildcards: scan=(\w+)\n    resources: (.*)", out)
    assert sorted(s for s, _ in scans) == sorted(rows(work)), scans
    for name, resources in scans:
        assert re.search(r"\bmem_mb=\d+", resources) and re.search(r"\bruntime=\d+", resources), resources
    assert "run_scan.py" in out  # printshellcmds: the profile's commands are shown


FAKE_SLURM = {
    # sbatch: note the call, run the --wrap command in the background in -D's
    # folder with SLURM's variables, answer like sbatch --parsable's caller expects.
    "sbatch": r"""#!/bin/bash
dir=.; wrap=; log=/dev/null
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  case "${args[i]}" in
    -D) dir="${args[i+1]}";; -o) log="${args[i+1]}";; --wrap=*) wrap="${args[i]#--wrap=}";;
  esac
done
id=$(( $(cat "$FAKE_SLURM_DIR/next" 2>/dev/null || echo 1000) + 1 )); echo $id > "$FAKE_SLURM_DIR/next"
rec=(); for a in "$@"; do [[ "$a" == --wrap=* ]] || rec+=("$a"); done
echo "sbatch ${rec[*]}" >> "$FAKE_SLURM_DIR/submissions"
( cd "$dir" && SLURM_JOB_ID=$id SLURM_CPUS_ON_NODE=1 bash -c "$wrap" > "${log//%j/$id}" 2>&1;
  echo $? > "$FAKE_SLURM_DIR/$id.rc" ) </dev/null >/dev/null 2>&1 &
echo "Submitted batch job $id"
""",
    "sacct": r"""#!/bin/bash
id="${@: -1}"
if [ -f "$FAKE_SLURM_DIR/$id.rc" ]; then
  [ "$(cat "$FAKE_SLURM_DIR/$id.rc")" = 0 ] && echo "$id|COMPLETED" || echo "$id|FAILED"
else echo "$id|RUNNING"; fi
""",
    "sacctmgr": "#!/bin/bash\necho '                 lab'\n",
    "srun": "#!/bin/bash\nwhile [[ \"$1\" == -* ]]; do shift; done\nexec \"$@\"\n",
}


def test_slurm_profile_submits_every_scan_through_sbatch(work, tmp_path):
    """The profile for real, with stand-ins for SLURM's commands: each scan is
    one sbatch call carrying its threads, memory and time."""
    fake = tmp_path / "slurm-bin"
    fake.mkdir()
    for name, text in FAKE_SLURM.items():
        (fake / name).write_text(text)
        (fake / name).chmod(0o755)
    env = dict(os.environ, PATH="%s:%s" % (fake, os.environ["PATH"]), FAKE_SLURM_DIR=str(fake),
               USER=os.environ.get("USER", "test"))
    run, seconds = snakemake(work, "--forceall", "--default-resources", "slurm_account=lab",
                             "slurm_partition=short", "--max-status-checks-per-second", "1",
                             profile=PROFILE, env=env)
    out = run.stdout + run.stderr
    assert run.returncode == 0, out[-4000:]
    with open(fake / "submissions") as f:
        submissions = f.read().splitlines()
    print("\n".join(submissions))
    n = len(rows(work))
    assert len(submissions) == n, submissions  # the scans; the aggregate runs locally
    for line in submissions:
        assert re.search(r"-A lab -p short -t \d+ --mem \d+ --cpus-per-task=1 -D ", line), line
    assert rows(work)["phantom_mha"]["status"] == "ok"


def test_example_configs_map_onto_this_gdm():
    """workflow/config/example.yaml and the README's example: every setting is a flag of this gdm."""
    import yaml
    sys.path.insert(0, os.path.join(SOURCE, "workflow", "scripts"))
    import cohort
    flags, _ = cohort.gdm_flags(GDM)
    with open(os.path.join(SOURCE, "README.md")) as f:
        readme = f.read()
    section = readme[readme.index("## Cohorts (Snakemake)"):]
    section = section[:section.index("\n## ", 3)]
    blocks = re.findall(r"```yaml\n(.*?)```", section, re.S)
    assert len(blocks) == 1
    with open(os.path.join(SOURCE, "workflow", "config", "example.yaml")) as f:
        configs = [yaml.safe_load(f), yaml.safe_load(blocks[0])]
    for config in configs:
        scans = cohort.expand_scans(config, SOURCE, flags)
        assert scans
        for name, path, settings in scans:
            arguments = cohort.gdm_arguments(name, settings, flags)
            assert arguments and all(a.startswith("--") for a in arguments[::2]), arguments
    tooth = dict((n, cohort.gdm_arguments(n, s, flags)) for n, _, s in cohort.expand_scans(configs[0], SOURCE, flags))
    # the group's `lod` (an alias) replaces the defaults' `lod-face-area`
    assert tooth["tooth_pulp"] == ["--threshold", "115", "--polarity", "dark", "--seed-index", "50,47,95",
                                   "--max-faces", "500000", "--lod-face-area", "4"]
    with pytest.raises(cohort.ConfigError, match="no option --no-such-flag"):
        cohort.gdm_arguments("x", {"options": {"no_such_flag": 1}}, flags)
    with pytest.raises(cohort.ConfigError, match="both set --max-faces"):
        cohort.gdm_arguments("x", {"face_budget": 10, "options": {"max_faces": 20}}, flags)
    with pytest.raises(cohort.ConfigError, match="sets --output itself"):
        cohort.gdm_arguments("x", {"options": {"output": "a.ply"}}, flags)
