"""The README's commands run as written: every command of its sh blocks (after the set-up block)
runs in a scratch folder that holds the demo's outputs, and exits 0 (compare's tolerance example
may exit 1, which is what it documents). `make -C pipelines` and `snakemake` lines are left out:
test_pipeline and test_snakemake run the pipelines."""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
import lodbake_test as lt  # noqa: E402


def readme_commands():
    text = open(os.path.join(lt.SOURCE, "README.md")).read()
    blocks = re.findall(r"```sh\n(.*?)```", text, re.S)
    commands = []
    for block in blocks[1:]:  # the first block installs and builds
        for line in block.splitlines():
            line = line.split("  #")[0].strip()
            if line and not line.startswith(("make ", "snakemake ")):
                commands.append(line)
    return commands


def main():
    work = lt.work_dir("readme")
    os.symlink(os.path.dirname(lt.BIN), os.path.join(work, "build"))
    os.symlink(os.path.join(lt.SOURCE, "scripts"), os.path.join(work, "scripts"))
    # The demo's outputs, made by the demo script's own commands.
    demo = open(os.path.join(lt.SOURCE, "scripts/demo.sh")).read()
    setup = [l for l in demo.splitlines() if l.startswith(("build/bin/", "mkdir"))]
    commands = setup + readme_commands()
    assert len(commands) > 15, commands
    failures = []
    for cmd in commands:
        p = subprocess.run(cmd, shell=True, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           timeout=600)
        allowed = {0, 1} if "--max-hausdorff" in cmd else {0}
        print("%d  %s" % (p.returncode, cmd))
        if p.returncode not in allowed:
            failures.append("%s -> exit %d: %s" % (cmd, p.returncode, p.stderr.strip()[-300:]))
    assert os.path.isfile(os.path.join(work, "out/seamball.lod0.glb")), "pack --split wrote no out/seamball.lod0.glb"
    if failures:
        raise AssertionError("README commands failed:\n" + "\n".join(failures))
    print("%d README commands ran" % len(commands))


if __name__ == "__main__":
    main()
