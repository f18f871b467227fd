#!/usr/bin/env python3
"""Rewrites opset-11 Clip nodes whose min/max come as constant inputs into the attribute form.

    python3 scripts/rewrite_onnx_clip.py IN.onnx OUT.onnx

OpenCV 4.6's ONNX importer only reads Clip's bounds from the `min`/`max` attributes (opset < 11);
Paddle2ONNX writes them as inputs (opset 11), so cv::dnn::readNetFromONNX refuses the PicoDet export
(models/picodet_s_416_coco/MANIFEST.md). Clip(x, lo, hi) = min(max(x, lo), hi) in both forms, so
the network computes exactly the same values. Only the Clip nodes change: bounds that are
initializers or Constant outputs are turned into attributes and the inputs dropped; the opset
import, every other node and every weight are left as they are. A Clip whose bound is computed at
run time cannot be rewritten and stops the script with an error.

Deterministic: the same input gives byte-identical output (scripts/assets.sha256 records it).
"""
import sys

import onnx
from onnx import helper, numpy_helper


def scalar_of(name, initializers, constants):
    if name in initializers:
        values = numpy_helper.to_array(initializers[name])
    elif name in constants:
        values = numpy_helper.to_array(constants[name])
    else:
        return None
    if values.size != 1:
        raise SystemExit(f"rewrite_onnx_clip: bound '{name}' has {values.size} values, expected 1")
    return float(values.reshape(-1)[0])


def main(argv):
    if len(argv) != 3:
        raise SystemExit("usage: rewrite_onnx_clip.py IN.onnx OUT.onnx")
    model = onnx.load(argv[1])
    graph = model.graph
    initializers = {t.name: t for t in graph.initializer}
    constants = {}
    for node in graph.node:
        if node.op_type == "Constant":
            for attr in node.attribute:
                if attr.name == "value":
                    constants[node.output[0]] = attr.t
    rewritten = 0
    for node in graph.node:
        if node.op_type != "Clip" or len(node.input) <= 1:
            continue
        bounds = {}
        for slot, key in ((1, "min"), (2, "max")):
            if slot < len(node.input) and node.input[slot]:
                value = scalar_of(node.input[slot], initializers, constants)
                if value is None:
                    raise SystemExit(f"rewrite_onnx_clip: {argv[1]}: Clip node '{node.name}' takes "
                                     f"its {key} from '{node.input[slot]}', which is not a constant")
                bounds[key] = value
        data = node.input[0]
        del node.input[:]
        node.input.append(data)
        for key in ("min", "max"):
            if key in bounds:
                node.attribute.append(helper.make_attribute(key, bounds[key]))
        rewritten += 1
    onnx.save(model, argv[2])
    print(f"rewrite_onnx_clip: {rewritten} Clip nodes rewritten to the attribute form -> {argv[2]}")


if __name__ == "__main__":
    main(sys.argv)
