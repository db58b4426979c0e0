#!/usr/bin/env bash
# Refresh the committed figures and tables of the documentation, doc/figures/. The main job
# (tools/main.sh) and the self-contact cases (tools/self_contact.sh) run as they always do and
# draw into output/figures/ (git-ignored); then every file they drew in this run that the
# documentation uses (linked as figures/<name> from doc/*.md or README.md, or already
# committed in doc/figures/) is copied into doc/figures/. Nothing else in the repository is
# written.
#
#   bash tools/doc_figures.sh                  # both (about 5 minutes on two idle cores)
#   bash tools/doc_figures.sh --main           # the main job's figures only
#   bash tools/doc_figures.sh --self-contact   # the self-contact figures only
#
# Afterwards `git status doc/figures` shows what changed: commit it with the numbers in
# doc/*.md that go with it. The figures of doc/ that neither job draws (the bench/ studies,
# the Taylor bar's FEM run at the paper's step) are listed at the end with the page that
# names the command drawing them.
# Exits non-zero when a job fails, or when a figure the documentation links to is missing
# from doc/figures/.
set -euo pipefail
cd "$(dirname "$0")/.."

run_main=1
run_self=1
case "${1:-}" in
  "") ;;
  --main) run_self=0 ;;
  --self-contact) run_main=0 ;;
  -h | --help) sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *)
    echo "doc_figures: error: unknown argument '$1' (use --main, --self-contact or none;" \
         "--help)" >&2
    exit 2 ;;
esac

figs=output/figures
docs=(doc/*.md README.md)
mkdir -p "$figs" doc/figures
# a file drawn after this stamp was drawn by this run (an older one in output/figures is not)
stamp=$(mktemp output/.doc_figures_stamp.XXXXXX)
trap 'rm -f "$stamp"' EXIT

if [ "$run_main" = 1 ]; then
  echo "== doc_figures: bash tools/main.sh"
  bash tools/main.sh
fi
if [ "$run_self" = 1 ]; then
  echo "== doc_figures: bash tools/self_contact.sh"
  bash tools/self_contact.sh
fi

# the names the documentation uses: its figures/<name> links and what doc/figures/ holds in git
used=$( { grep -ohE 'figures/[A-Za-z0-9_.-]+\.(png|pdf|svg|md)' "${docs[@]}" \
            | sed 's#^figures/##'
          git ls-files doc/figures 2>/dev/null | sed 's#^doc/figures/##'; } | sort -u)

echo "== doc_figures: $figs/ -> doc/figures/"
ncopied=0
left=()
while IFS= read -r -d '' f; do
  name=${f#"$figs"/}
  if grep -qxF -- "$name" <<< "$used"; then
    cp "$f" "doc/figures/$name"
    echo "  doc/figures/$name"
    ncopied=$((ncopied + 1))
  else
    left+=("$name")
  fi
done < <(find "$figs" -maxdepth 1 -type f -newer "$stamp" -print0 | sort -z)
if [ "$ncopied" = 0 ]; then
  echo "doc_figures: error: no figure drawn into $figs/ in this run" >&2
  exit 1
fi
if [ "${#left[@]}" -gt 0 ]; then
  echo "  drawn but not used by the documentation (left in $figs/): ${left[*]}"
fi

# every link of the documentation must resolve; say which ones this command does not draw
missing=0
while IFS= read -r name; do
  [ -n "$name" ] || continue
  if [ ! -f "doc/figures/$name" ]; then
    echo "doc_figures: error: the documentation links figures/$name, which is not in" \
         "doc/figures/" >&2
    missing=1
  elif ! [ "$figs/$name" -nt "$stamp" ]; then
    pages=$(grep -lF "figures/$name" "${docs[@]}" | tr '\n' ' ')
    echo "  not drawn by this command: figures/$name (its command: ${pages% })"
  fi
done < <(grep -ohE 'figures/[A-Za-z0-9_.-]+\.(png|pdf|svg|md)' "${docs[@]}" \
           | sed 's#^figures/##' | sort -u)
[ "$missing" = 0 ] || exit 1
echo "doc_figures: $ncopied files copied into doc/figures/; git status doc/figures shows the changes"
