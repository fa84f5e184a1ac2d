"""docs/options.md lists every option as the code declares it: its generated section is the output
of `gimp -gimp_options_markdown` (the option table and the dimension table), byte for byte."""
import os
import subprocess
import sys
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
p = subprocess.run([args.gimp, "-gimp_options_markdown"], capture_output=True, text=True, env=env)
c.check("gimp -gimp_options_markdown runs", p.returncode == 0 and p.stdout.startswith("| option"),
        "exit %d" % p.returncode)
doc = open(os.path.join(args.root, "docs", "options.md")).read()
begin = "<!-- begin: gimp -gimp_options_markdown"
end = "<!-- end: gimp -gimp_options_markdown -->"
ok = begin in doc and end in doc
section = doc[doc.index(begin):doc.index(end)].split("\n", 1)[1] if ok else ""
c.check("docs/options.md has the generated section", ok, "markers %s" % ("found" if ok else "missing"))
if ok and section != p.stdout:
    have, want = section.splitlines(), p.stdout.splitlines()
    first = next((i for i in range(min(len(have), len(want))) if have[i] != want[i]),
                 min(len(have), len(want)))
    sys.stdout.write("first difference at line %d of the section:\n  docs: %s\n  code: %s\n" % (
        first + 1, have[first] if first < len(have) else "(end)",
        want[first] if first < len(want) else "(end)"))
c.check("the section equals the code's table", ok and section == p.stdout,
        "%d lines in docs, %d from the code (regenerate: build/gimp -gimp_options_markdown)" % (
            len(section.splitlines()), len(p.stdout.splitlines())))
c.done()
