#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# Docs are code: compiles every ```cpp snippet of README.md and docs/ against an installed codrive,
# checks every documented codrive command line against the real tools, and checks the per-command
# pages in docs/cli/ against each tool's --help. Prints "ok: ..." / "FAILED: ..." lines.
#
# Snippet convention (also in docs/getting-started.md, "Code on these pages"):
#  * a block with `int main(` is a whole program and is compiled as it stands;
#  * any other block is a fragment: its leading `#include` lines stay at the top, every installed
#    codrive header is included, `using namespace codrive;` and std::chrono_literals are in
#    effect, and the rest becomes the body of a function with these names in scope:
#      codrive::IClock& clock, codrive::ICanBus& bus, codrive::EventLoop& loop
#    Lines before a line `// ---` (if there is one) go at namespace scope (helper declarations).
#  * each program is linked (pkg-config codrive-sim, which includes codrive), not run.
import argparse
import os
import re
import shlex
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
TOOLS = ("codrive", "codrive-dump", "codrive-sim", "codrive-ecat-sim")
# docs/cli/<page>.md documents the tool (and subcommand) in its name.
PAGES = {
    "codrive": ["codrive"],
    "codrive-scan": ["codrive", "scan"],
    "codrive-sdo": ["codrive", "sdo"],
    "codrive-nmt": ["codrive", "nmt"],
    "codrive-supervise": ["codrive", "supervise"],
    "codrive-drive": ["codrive", "drive"],
    "codrive-save": ["codrive", "save"],
    "codrive-restore": ["codrive", "restore"],
    "codrive-commission": ["codrive", "commission"],
    "codrive-run": ["codrive", "run"],
    "codrive-eds": ["codrive", "eds"],
    "codrive-esi": ["codrive", "esi"],
    "codrive-ecat": ["codrive", "ecat"],
    "codrive-bus": ["codrive", "bus"],
    "codrive-latency": ["codrive", "latency"],
    "codrive-dump": ["codrive-dump"],
    "codrive-sim": ["codrive-sim"],
    "codrive-ecat-sim": ["codrive-ecat-sim"],
}


def markdown_files():
    files = [os.path.join(ROOT, "README.md")]
    for d, _, names in os.walk(os.path.join(ROOT, "docs")):
        files += [os.path.join(d, n) for n in sorted(names) if n.endswith(".md")]
    return sorted(files)


def rel(path):
    return os.path.relpath(path, ROOT)


def fenced_blocks(path):
    """Yields (language, first line number, lines) for every fenced block of a markdown file."""
    lang, start, body = None, 0, []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            m = re.match(r"^\s*```(\S*)", line)
            if m and lang is None:
                lang, start, body = m.group(1) or "text", n + 1, []
            elif m:
                yield lang, start, body
                lang = None
            elif lang is not None:
                body.append(line.rstrip("\n"))


# ------------------------------------------------------------------------------------------------
# C++ snippets
# ------------------------------------------------------------------------------------------------
def snippet_source(lines, headers, origin):
    text = "\n".join(lines)
    out = [f"// generated from {origin} by tests/install/check_docs.py"]
    if "int main(" in text:
        return "\n".join(out + lines) + "\n"
    includes = []
    body = list(lines)
    while body and (body[0].startswith("#include") or not body[0].strip()):
        includes.append(body.pop(0))
    scope = []
    if any(line.strip() == "// ---" for line in body):
        cut = [line.strip() for line in body].index("// ---")
        scope, body = body[:cut], body[cut + 1 :]
    out += [f"#include <{h}>" for h in headers] + includes
    out += ["using namespace codrive;", "using namespace std::chrono_literals;"]
    out += scope
    out += [
        "int codrive_doc_snippet([[maybe_unused]] codrive::IClock& clock,",
        "                        [[maybe_unused]] codrive::ICanBus& bus,",
        "                        [[maybe_unused]] codrive::EventLoop& loop) {",
        f"#line {0}",
    ]
    out += body
    out += ["    return 0;", "}", "int main() { return 0; }"]
    return "\n".join(out) + "\n"


def check_snippets(prefix, work):
    env = dict(os.environ, PKG_CONFIG_PATH=os.path.join(prefix, "lib", "pkgconfig"))
    flags = subprocess.run(["pkg-config", "--cflags", "--libs", "codrive-sim"], env=env,
                           capture_output=True, text=True, check=True).stdout.split()
    inc = os.path.join(prefix, "include")
    headers = []
    for d, _, names in os.walk(os.path.join(inc, "codrive")):
        headers += [os.path.relpath(os.path.join(d, n), inc) for n in names if n.endswith(".hpp")]
    headers.sort()
    jobs = []
    for md in markdown_files():
        for lang, start, lines in fenced_blocks(md):
            if lang != "cpp":
                continue
            origin = f"{rel(md)}:{start}"
            src = snippet_source(lines, headers, origin)
            # Error lines point into the page: the wrapper's #line maps the body to the markdown.
            first_body = start + next((i for i, l in enumerate(lines)
                                       if not (l.startswith("#include") or not l.strip())), 0)
            if any(l.strip() == "// ---" for l in lines):
                first_body = start + [l.strip() for l in lines].index("// ---") + 1
            src = src.replace("#line 0", f'#line {first_body} "{rel(md)}"')
            name = re.sub(r"[^A-Za-z0-9]+", "_", origin)
            path = os.path.join(work, name + ".cpp")
            with open(path, "w", encoding="utf-8") as f:
                f.write(src)
            jobs.append((origin, path))

    def build(job):
        origin, path = job
        r = subprocess.run(["g++", "-O0", "-w", "-o", path[:-4], path] + flags,
                           capture_output=True, text=True, cwd=work)
        return origin, r

    failed = 0
    with ThreadPoolExecutor(max_workers=int(os.environ.get("CODRIVE_JOBS", "2"))) as pool:
        for origin, r in pool.map(build, jobs):
            if r.returncode == 0:
                print(f"ok: snippet {origin} compiles and links")
            else:
                failed += 1
                errs = [l for l in r.stderr.splitlines() if "error" in l][:5]
                print(f"FAILED: snippet {origin} does not build:\n    " + "\n    ".join(errs))
    if not jobs:
        print("FAILED: no ```cpp snippet found in the docs")
        failed += 1
    return failed


# ------------------------------------------------------------------------------------------------
# Command lines and --help
# ------------------------------------------------------------------------------------------------
def help_text(bindir, argv):
    if not os.access(os.path.join(bindir, argv[0]), os.X_OK):
        return 127, f"{argv[0]}: not found in {bindir}"
    r = subprocess.run([os.path.join(bindir, argv[0])] + argv[1:] + ["--help"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=30)
    return r.returncode, r.stdout + r.stderr


def help_sections(text):
    """Options, positionals and subcommands listed by a CLI11 --help text ("Options:",
    "Positionals:", "Subcommands:" sections; an entry is a line indented by two spaces whose first
    word is the name, e.g. `  -i,--iface TEXT Excludes: --ethercat`)."""
    options, positionals, subcommands = set(), [], []
    section = None
    for line in text.splitlines():
        if re.match(r"^[A-Za-z ]+:$", line.strip()) and not line.startswith("   "):
            section = line.strip()[:-1].upper()
            continue
        if not re.match(r"^  \S", line):
            continue
        words = line.split()
        first = words[0]
        if section == "OPTIONS":
            options |= {n.split("=")[0] for n in first.split(",") if n.startswith("-")}
        elif section == "POSITIONALS":
            spec = re.split(r"\s{2,}", line.strip())[0]
            positionals.append((first, "..." in spec))
        elif section == "SUBCOMMANDS":
            subcommands.append(first)
    return options, positionals, subcommands


class Cli:
    def __init__(self, bindir):
        self.bindir = bindir
        self.cache = {}

    def info(self, argv):
        key = tuple(argv)
        if key not in self.cache:
            rc, text = help_text(self.bindir, list(argv))
            self.cache[key] = (rc, text) + help_sections(text)
        return self.cache[key]


def split_command(text):
    """A documented command: text up to a '#' comment, a pipe or '&&', tokenised like a shell."""
    text = re.split(r"\s+#\s|\s*&&\s*|\s\|\s*(?=(?:head|tail|grep|tee|less|sort|wc)\b)|\s*;\s*$",
                    text)[0].strip()
    text = re.sub(r"^\$\s+", "", text)
    text = re.sub(r"\s+&$", "", text)
    try:
        return shlex.split(text)
    except ValueError:
        return text.split()


def documented_commands():
    """(origin, text, is_inline) for every codrive tool invocation in a fenced block or inline
    code span."""
    tool_re = r"(?:[\w./-]*/)?(?:%s)" % "|".join(re.escape(t) for t in sorted(TOOLS, key=len,
                                                                         reverse=True))
    found = []
    for md in markdown_files():
        in_block = None
        with open(md, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                if re.match(r"^\s*```", line):
                    in_block = None if in_block is not None else re.match(r"^\s*```(\S*)", line).group(1)
                    continue
                if in_block is not None:
                    if in_block in ("", "sh", "bash", "console", "text"):
                        m = re.match(r"^\s*(?:\$\s+)?(?:sudo\s+)?(?:.*(?:run-in-vcan|session)\.sh\s+(?:-\S+\s+)*)?"
                                     r"(%s)(\s.*)?$" % tool_re, line.rstrip("\n"))
                        if m and not re.match(r"^\s*%s\s*:" % tool_re, line):
                            found.append((f"{rel(md)}:{n}", line[m.start(1):].rstrip("\n"), False))
                    continue
                for span in re.findall(r"`([^`]+)`", line):
                    if re.match(r"^%s\s+-?-?\w" % tool_re, span):
                        found.append((f"{rel(md)}:{n}", span, True))
    return found


def check_command(cli, text, mention=False):
    """Returns None if the command line fits the tool's --help, else the reason. A mention (an
    inline code span in prose) that ends in an option without its value, e.g. `codrive scan
    --ethercat`, is checked like a synopsis: its subcommands and options must exist."""
    argv = split_command(text)
    if not argv:
        return "empty command"
    argv[0] = os.path.basename(argv[0])
    synopsis = any(c in text for c in "[]|") or "..." in text or re.search(r"\b[A-Z]{2,}\b", text)
    chain = [argv[0]]
    rest = argv[1:]
    # Walk down the subcommands: the first token that names one of the current command's
    # subcommands (options may come first, CLI11 accepts them anywhere).
    while True:
        rc, _, options, positionals, subs = cli.info(chain)
        if rc != 0:
            return f"`{' '.join(chain)} --help` failed (exit {rc})"
        nxt = next((i for i, t in enumerate(rest) if t in subs), None)
        alternatives = next((i for i, t in enumerate(rest) if "|" in t and
                             all(a in subs for a in t.split("|"))), None)
        if nxt is None or (alternatives is not None and alternatives < nxt):
            break
        chain.append(rest[nxt])
        rest = rest[:nxt] + rest[nxt + 1:]
    # Every option named must exist on this command, a parent or (synopsis `a|b|c`) one of the
    # alternative subcommands and their subcommands.
    known = set()
    for i in range(1, len(chain) + 1):
        known |= cli.info(chain[:i])[2]
    todo = [chain + [a] for t in rest if "|" in t for a in t.split("|") if a in cli.info(chain)[4]]
    while todo:
        sub = todo.pop()
        known |= cli.info(sub)[2]
        todo += [sub + [s] for s in cli.info(sub)[4]]
    known |= {"--help", "-h"}
    # Options a tool handles before its parser and names in its description (codrive-sim
    # --ethercat hands over to codrive-ecat-sim) are in the --help text too.
    known |= set(re.findall(r"(?<![\w-])(--[a-z][\w-]*)", cli.info(chain[:1])[1]))
    for tok in rest:
        for alt in tok.split("|"):
            opt = alt.split("=")[0].strip("[]")
            if re.match(r"^--?[A-Za-z]", opt) and opt not in known:
                return f"`{' '.join(chain)}` has no option {opt}"
    if subs and not any(t in subs or "|" in t for t in rest) and not synopsis and not mention:
        if cli.info(chain)[3] == []:
            return f"`{' '.join(chain)}` needs a subcommand ({', '.join(subs)})"
    if mention and rest and option_value_counts(cli, chain).get(rest[-1], 0):
        synopsis = True  # `codrive scan --ethercat` in prose names the option, gives no value
    if synopsis:
        return None
    # A literal command: CLI11 parses it for real up to --help (options, values, subcommands),
    # and the positionals must fit the command's POSITIONALS.
    rc, out = help_text(cli.bindir, [chain[0]] + argv[1:])
    if rc != 0:
        return f"rejected by the tool: {out.strip().splitlines()[0] if out.strip() else rc}"
    _, _, options, positionals, _ = cli.info(chain)
    takes_value = option_value_counts(cli, chain)
    count, i = 0, 0
    while i < len(rest):
        tok = rest[i]
        if tok.startswith("-") and len(tok) > 1 and not re.match(r"^-\d", tok):
            if "=" not in tok and takes_value.get(tok, 0):
                i += takes_value[tok]
        else:
            count += 1
        i += 1
    if not any(multi for _, multi in positionals) and count > len(positionals):
        names = " ".join(p for p, _ in positionals) or "none"
        return f"{count} positional argument(s) but `{' '.join(chain)}` takes {names}"
    return None


def option_value_counts(cli, chain):
    """Options that take a value: CLI11 prints a type after the names (TEXT, INT, UINT, FLOAT...)."""
    counts = {}
    for i in range(1, len(chain) + 1):
        text = cli.info(chain[:i])[1]
        for line in text.splitlines():
            if not re.match(r"^  -", line):
                continue
            words = line.split()
            value = 1 if len(words) > 1 and re.match(r"^[A-Z][A-Z0-9_]*(=|$|:)", words[1]) and \
                not words[1].endswith(":") else 0
            for name in words[0].split(","):
                counts[name.split("=")[0]] = value
    return counts


def check_commands(bindir):
    cli = Cli(bindir)
    failed = 0
    commands = documented_commands()
    for origin, text, mention in commands:
        why = check_command(cli, text, mention)
        if why:
            failed += 1
            print(f"FAILED: {origin}: `{text}`: {why}")
        else:
            print(f"ok: {origin}: `{text}`")
    if not commands:
        print("FAILED: no codrive command line found in the docs")
        failed += 1
    return failed


def page_options(path):
    """Options a docs/cli page documents: `--x` / `-x` in its option tables' first column."""
    opts = set()
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("|"):
                first = line.split("|")[1]
                opts |= set(re.findall(r"(?<![\w-])(--?[A-Za-z][\w-]*)", first))
    return opts


def check_pages(bindir):
    cli = Cli(bindir)
    failed = 0
    pagedir = os.path.join(ROOT, "docs", "cli")
    for page, argv in PAGES.items():
        path = os.path.join(pagedir, page + ".md")
        if not os.path.exists(path):
            print(f"FAILED: docs/cli/{page}.md is missing")
            failed += 1
            continue
        # The tool's options: this command and every subcommand below it.
        listed, todo = set(), [argv]
        while todo:
            chain = todo.pop()
            rc, _, options, _, subs = cli.info(chain)
            if rc != 0:
                print(f"FAILED: `{' '.join(chain)} --help` exits {rc}")
                failed += 1
                continue
            listed |= options
            if page != "codrive":  # the codrive page lists the subcommands, each has its own page
                todo += [chain + [s] for s in subs]
        listed -= {"-h", "--help"}
        documented = page_options(path) - {"-h", "--help"}
        missing = sorted(listed - documented)
        extra = sorted(documented - listed)
        if missing or extra:
            failed += 1
            print(f"FAILED: docs/cli/{page}.md vs `{' '.join(argv)} --help`: "
                  f"undocumented {missing}, not in --help {extra}")
        else:
            print(f"ok: docs/cli/{page}.md documents the {len(listed)} options of "
                  f"`{' '.join(argv)}`")
    return failed


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("what", choices=["snippets", "commands", "pages"])
    ap.add_argument("--prefix", help="installed codrive (snippets; its bin/ for the others)")
    ap.add_argument("--bin", help="directory holding the tools (default PREFIX/bin)")
    ap.add_argument("--work", help="scratch directory for generated sources")
    a = ap.parse_args()
    bindir = a.bin or os.path.join(a.prefix or "", "bin")
    if a.what == "snippets":
        work = a.work or tempfile.mkdtemp(prefix="codrive-snippets.")
        os.makedirs(work, exist_ok=True)
        failed = check_snippets(a.prefix, work)
    elif a.what == "commands":
        failed = check_commands(bindir)
    else:
        failed = check_pages(bindir)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
