#!/usr/bin/env python3
"""Rewrites the XFeat export (xfeat_640x640.onnx) into a model that takes any image size that is a
multiple of 32 (xfeat_any_size.onnx).

    python3 scripts/rewrite_onnx_xfeat.py IN.onnx OUT.onnx

The export (models/xfeat/MANIFEST.md) is fully convolutional except for two places where PyTorch's
tracer wrote the 640x640 input size into the graph as constants (1, 2); one input is added (3):

1. the keypoint head's input, XFeat's `_unfold2d(x, 8)` of the normalised grey image (each 8x8
   cell's 64 pixels as 64 channels, channel = 8 * row + column inside the cell), traced as 80
   Slice / Transpose / Unsqueeze nodes per axis, two Concats, a Reshape to [1, 1, 80, 80, 64], a
   Transpose and a Reshape to [1, 64, 80, 80]. ONNX's SpaceToDepth with blocksize 8 is that same
   rearrangement for one channel (output channel (bh * 8 + bw) * C + c = bh * 8 + bw), in one node
   and for any size;
2. the two Resize nodes that bring the 1/16 and 1/32 feature maps to the 1/8 map's size, whose
   target size is the constant [80, 80]. It becomes the 1/8 map's own height and width, read
   from its shape at run time (what `F.interpolate(size=x3.shape[-2:])` did before tracing).

3. a new input `contrast` (one float) multiplies the instance-normalised grey image. The export
   normalises the image by its own mean and variance; when a 640x480 frame was padded to 640x640
   with its mean colour, the flat fill diluted the variance by the share of fill, so the network
   saw the image's contrast raised by sqrt(640 * 640 / (640 * 480)) = 1.15. zeroreg gives that
   factor (src/features/xfeat_extractor.cpp), so the features at the image's own size are those
   of the padded square every default was measured with; 1 gives upstream XFeat's normalisation.

Every weight and every other node is kept as it is, so on a 640x640 input with contrast 1 the
rewritten model computes the same outputs as the original (tests/features/xfeat_test.cpp checks it on real
frames). Why: a 640x480 frame had to be padded to 640x640, a quarter of XFeat's work spent on
fill (docs/SPEED.md, "XFeat at the image's own size").

Deterministic: the same input gives byte-identical output (scripts/assets.sha256 records it).
"""
import sys

import onnx
from onnx import helper

# Tensor names in the export (pinned by its sha256 in scripts/assets.sha256).
NORMALISED_IMAGE = "126"  # InstanceNormalization output, 1 x 1 x H x W
UNFOLDED = "1250"  # Reshape output, 1 x 64 x H/8 x W/8: the keypoint head's input
EIGHTH_MAP = "176"  # the backbone's 1/8-resolution map, 1 x 64 x H/8 x W/8
RESIZE_SIZE_CONCATS = ("223", "238")  # Concat(N and C of the map, [80, 80]) -> Resize sizes
CONTRAST = "contrast"  # new input, 1 float: multiplies the normalised image
OUTPUT_DIMS = {"output": 64, "1266": 65, "266": 1}


def fail(message):
    raise SystemExit(f"rewrite_onnx_xfeat: {message} (expected the XFeat export of models/xfeat)")


def main(argv):
    if len(argv) != 3:
        raise SystemExit("usage: rewrite_onnx_xfeat.py IN.onnx OUT.onnx")
    model = onnx.load(argv[1])
    graph = model.graph
    producer = {out: node for node in graph.node for out in node.output}
    for name in (NORMALISED_IMAGE, UNFOLDED, EIGHTH_MAP) + RESIZE_SIZE_CONCATS:
        if name not in producer:
            fail(f"no node produces tensor '{name}'")
    if producer[NORMALISED_IMAGE].op_type != "InstanceNormalization":
        fail(f"tensor '{NORMALISED_IMAGE}' is not the InstanceNormalization output")
    if producer[UNFOLDED].op_type != "Reshape":
        fail(f"tensor '{UNFOLDED}' is not a Reshape output")

    # 1. The unfold: every node between the normalised image and the keypoint head's input.
    unfold = set()
    stack = [UNFOLDED]
    while stack:
        name = stack.pop()
        node = producer.get(name)
        if name == NORMALISED_IMAGE or node is None or id(node) in unfold:
            continue
        if node.op_type not in ("Reshape", "Transpose", "Concat", "Unsqueeze", "Slice", "Constant"):
            fail(f"unexpected {node.op_type} node '{node.name}' in the unfold")
        unfold.add(id(node))
        stack.extend(node.input)
    # Constants the unfold shares with the rest of the graph stay.
    kept_inputs = {i for n in graph.node if id(n) not in unfold for i in n.input}
    kept_inputs |= {o.name for o in graph.output}
    removed = [n for n in graph.node
               if id(n) in unfold and not (n.op_type == "Constant" and n.output[0] in kept_inputs)]
    removed_ids = {id(n) for n in removed}
    if sum(n.op_type == "Slice" for n in removed) != 160:
        fail("the unfold is not 2 x 80 Slice nodes")

    # 2. The Resize target sizes: [N, C] of the map to resize, then H, W of the 1/8 map.
    shape_name, hw_name = "xfeat_eighth_map_shape", "xfeat_eighth_map_hw"
    starts, ends = "xfeat_hw_starts", "xfeat_hw_ends"
    new_nodes = [
        helper.make_node("SpaceToDepth", [NORMALISED_IMAGE], [UNFOLDED], name="unfold2d_8",
                         blocksize=8),
        helper.make_node("Shape", [EIGHTH_MAP], [shape_name], name=shape_name),
        helper.make_node("Constant", [], [starts], name=starts,
                         value=helper.make_tensor(starts, onnx.TensorProto.INT64, [1], [2])),
        helper.make_node("Constant", [], [ends], name=ends,
                         value=helper.make_tensor(ends, onnx.TensorProto.INT64, [1], [4])),
        helper.make_node("Slice", [shape_name, starts, ends], [hw_name], name=hw_name),
    ]
    for name in RESIZE_SIZE_CONCATS:
        concat = producer[name]
        if concat.op_type != "Concat" or len(concat.input) != 2:
            fail(f"tensor '{name}' is not a two-input Concat")
        concat.input[1] = hw_name

    # 3. A contrast factor on the normalised image, given with every run (see the docstring).
    norm = producer[NORMALISED_IMAGE]
    norm.output[0] = NORMALISED_IMAGE + "_unscaled"
    contrast_node = helper.make_node("Mul", [norm.output[0], CONTRAST], [NORMALISED_IMAGE],
                                     name="contrast")
    graph.input.append(helper.make_tensor_value_info(CONTRAST, onnx.TensorProto.FLOAT, [1]))

    nodes = [n for n in graph.node if id(n) not in removed_ids]
    # Topological order: the new nodes go right after the node producing their input.
    ordered = []
    for node in nodes:
        ordered.append(node)
        if node is norm:
            ordered.extend([contrast_node, new_nodes[0]])
        if EIGHTH_MAP in node.output:
            ordered.extend(new_nodes[1:])
    del graph.node[:]
    graph.node.extend(ordered)
    # Constant size [80, 80] initialisers no longer used by any node.
    used = {i for n in graph.node for i in n.input}
    initializers = [t for t in graph.initializer if t.name in used]
    del graph.initializer[:]
    graph.initializer.extend(initializers)

    # 4. Symbolic height and width on the input and the outputs; no stale fixed shapes inside.
    dims = graph.input[0].type.tensor_type.shape.dim
    dims[2].Clear()
    dims[2].dim_param = "height"
    dims[3].Clear()
    dims[3].dim_param = "width"
    for output in graph.output:
        if output.name not in OUTPUT_DIMS:
            fail(f"unexpected output '{output.name}'")
        out_dims = output.type.tensor_type.shape.dim
        for k, value in enumerate([None, OUTPUT_DIMS[output.name], "height/8", "width/8"]):
            out_dims[k].Clear()
            if k == 0:
                out_dims[k].dim_value = 1
            elif isinstance(value, int):
                out_dims[k].dim_value = value
            else:
                out_dims[k].dim_param = value
    del graph.value_info[:]

    onnx.checker.check_model(model)
    with open(argv[2], "wb") as f:
        f.write(model.SerializeToString(deterministic=True))


if __name__ == "__main__":
    main(sys.argv)
