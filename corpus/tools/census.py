#!/usr/bin/env python3
"""Static keyword census of an LS-DYNA deck (follows *INCLUDE files that exist: the keywords
that cleave's reader does not name, from its source) and
iterative peeling of unsupported-keyword blocks with `cleave check` (env CLEAVE, PEEL_ROOT).
usage: census.py DECK [--peel]"""
import os, re, sys, subprocess, shutil, tempfile, json
CLEAVE = os.path.abspath(os.environ.get("CLEAVE", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "target", "release", "cleave")))
# The keywords the reader names, taken from its source (each is read, or refused or warned
# about by name, so `cleave check` says which), so that this list never goes stale.
SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "crates", "cleave-io", "src", "deck")
ACCEPT = set()
for d, _, files in os.walk(SRC):
    for f in files:
        if f.endswith(".rs"):
            ACCEPT |= set(re.findall(r'"(\*[A-Z0-9_]+)"', open(os.path.join(d, f)).read()))
ACCEPT |= {"*END"}
WARN = {"*CONTROL_ENERGY","*CONTROL_OUTPUT","*CONTROL_CPU","*CONTROL_PARALLEL","*CONTROL_DEBUG",
 "*CONTROL_REMOVE_ADDITIONAL_DATA"}
def base(kw):
    b = kw
    if b.endswith("_TITLE") and (b.startswith(("*MAT_","*SECTION_","*SET_")) or b=="*DEFINE_CURVE_TITLE"):
        b = b[:-6]
    return b
def status(kw):
    b = base(kw)
    if b in ACCEPT: return "ok"
    if b in WARN or b.startswith("*CONTROL_MPP_") or b.startswith("*DATABASE_"): return "warn"
    return "unsupported"
def keywords(path, seen=None):
    seen = seen if seen is not None else set()
    out = []
    if path in seen or not os.path.exists(path): return out
    seen.add(path)
    lines = open(path, errors="replace").read().splitlines()
    i = 0
    while i < len(lines):
        l = lines[i]
        if l.startswith("*"):
            kw = l.split()[0].upper()
            out.append((kw, path, i+1))
            if kw == "*INCLUDE":
                j = i+1
                while j < len(lines) and (lines[j].startswith("$") or not lines[j].strip()): j += 1
                if j < len(lines) and not lines[j].startswith("*"):
                    inc = lines[j].strip()
                    out += keywords(os.path.join(os.path.dirname(path), inc), seen)
        i += 1
    return out
def peel(deck):
    d = tempfile.mkdtemp()
    root = os.environ.get("PEEL_ROOT") or os.path.dirname(os.path.abspath(deck))
    shutil.copytree(root, d, dirs_exist_ok=True)
    target = os.path.join(d, os.path.relpath(os.path.abspath(deck), root))
    found = []
    for _ in range(80):
        p = subprocess.run([CLEAVE, "check", os.path.basename(target)], capture_output=True, text=True, cwd=os.path.dirname(target))
        if p.returncode == 0:
            found.append(("PASS", "")); break
        err = [l for l in p.stderr.splitlines() if l.startswith("error")]
        msg = err[0] if err else (p.stderr.strip().splitlines() or ["?"])[0]
        m = re.match(r"error: (.+?):(\d+): (\*[A-Z0-9_]+): (keyword not supported|not supported)", msg)
        if not m:
            found.append(("STOP", msg.replace(d + "/", ""))); break
        f, ln, kw = m.group(1), int(m.group(2)), m.group(3)
        fp = f if os.path.isabs(f) else os.path.join(os.path.dirname(target), f)
        L = open(fp, errors="replace").read().splitlines()
        j = ln
        while j < len(L) and not L[j].startswith("*"): j += 1
        del L[ln-1:j]
        open(fp, "w").write("\n".join(L) + "\n")
        found.append((kw, ""))
    shutil.rmtree(d)
    return found
if __name__ == "__main__":
    deck = sys.argv[1]
    kws = keywords(deck)
    from collections import OrderedDict
    st = OrderedDict()
    for kw, f, ln in kws:
        st.setdefault(kw, status(kw))
    res = {"deck": deck, "unsupported": [k for k, s in st.items() if s == "unsupported"],
           "warn": [k for k, s in st.items() if s == "warn"],
           "has_shell": any(k.startswith(("*ELEMENT_SHELL","*ELEMENT_BEAM","*ELEMENT_TSHELL","*ELEMENT_DISCRETE","*ELEMENT_SPH","*SECTION_SHELL","*SECTION_BEAM")) for k in st),
           "has_solid": any(k.startswith("*ELEMENT_SOLID") for k in st)}
    if "--peel" in sys.argv:
        res["peel"] = peel(deck)
    print(json.dumps(res))
