"""docs/schemas: one JSON Schema per tool report (draft 2020-12). Each schema is valid, every
tool's real --report on a generated sample validates against its schema (lodbake's embeds the
stage schemas by $ref), and reports with a missing key or a wrong type are rejected."""
import copy
import json
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
from lodbake_test import SOURCE, make_samples, run, skip, tool, work_dir  # noqa: E402

try:
    import jsonschema
except ImportError:
    jsonschema = None

SCHEMAS = os.path.join(SOURCE, "docs/schemas")
TOOLS = ["simplify", "agsphere-build", "parameterize", "texture-refine", "pack", "compare", "lodbake"]


def load_schemas():
    return {t: json.load(open(os.path.join(SCHEMAS, t + ".schema.json"))) for t in TOOLS}


def validator(schemas, tool_name):
    """A draft 2020-12 validator of `tool_name`'s schema that resolves the relative $refs between
    the schemas (the `referencing` registry of jsonschema >= 4.18, else RefResolver)."""
    cls = jsonschema.Draft202012Validator
    try:
        from referencing import Registry, Resource
    except ImportError:
        store = {t + ".schema.json": s for t, s in schemas.items()}
        return cls(schemas[tool_name], resolver=jsonschema.RefResolver("", schemas[tool_name], store=store))
    registry = Registry().with_resources((t + ".schema.json", Resource.from_contents(s)) for t, s in schemas.items())
    return cls(schemas[tool_name], registry=registry)


def errors(schemas, tool_name, report):
    return ["%s: %s" % ("/".join(map(str, e.absolute_path)), e.message)
            for e in validator(schemas, tool_name).iter_errors(report)]


class ReportSchemas(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if jsonschema is None:
            skip("python3-jsonschema is missing (apt-get install python3-jsonschema; scripts/setup-debian.sh)")
        for t in TOOLS + ["make-samples"]:
            if not os.path.exists(tool(t)):
                skip(t + " is not built")
        cls.schemas = load_schemas()
        d = work_dir("schemas")
        s = make_samples(os.path.join(d, "samples"))
        src, wall = os.path.join(s, "colors.glb"), os.path.join(s, "wall5.glb")
        f = {k: os.path.join(d, "colors." + k) for k in ("mr.glb", "uv.glb", "tex.glb", "lod.glb", "ag.glb", "chain.glb")}
        r = {t: os.path.join(d, t + ".json") for t in TOOLS}
        q = ["-q", "--report"]
        run([tool("simplify"), "-i", src, "-o", f["mr.glb"], "--ratio", "0.5,0.1"] + q + [r["simplify"]])
        run([tool("agsphere-build"), "-i", wall, "-o", f["ag.glb"], "--ratio", "0.5,0.1", "--view", "0,0,5"] + q
            + [r["agsphere-build"]])
        run([tool("parameterize"), "-i", f["mr.glb"], "-o", f["uv.glb"], "--size", "128"] + q + [r["parameterize"]])
        run([tool("texture-refine"), "-i", f["uv.glb"], "-o", f["tex.glb"], "--size", "128", "--sizes", "64,128"] + q
            + [r["texture-refine"]])
        run([tool("pack"), "-i", f["tex.glb"], "-o", f["lod.glb"], "--max-size", "128", "--samples", "16"] + q + [r["pack"]])
        run([tool("compare"), src, f["lod.glb"], "--views", "2", "--resolution", "64", "--samples", "2000", "--report",
             r["compare"]])
        run([tool("lodbake"), "-i", src, "-o", f["chain.glb"], "--ratio", "0.5", "--no-texture-refine", "--size", "128",
             "--max-size", "128", "--samples", "16", "--lod0", "original"] + q + [r["lodbake"]])
        cls.reports = {t: json.load(open(r[t])) for t in TOOLS}
        # Over the triangle budget T0 is compared with nothing and not measured.
        over = os.path.join(d, "over.json")
        run([tool("texture-refine"), "-i", f["uv.glb"], "-o", os.path.join(d, "over.tex.glb"), "--size", "128", "--sizes",
             "64,128", "--max-refine-triangles", "1"] + q + [over])
        cls.over_budget = json.load(open(over))

    def test_schemas_are_valid(self):
        for t, s in self.schemas.items():
            with self.subTest(schema=t):
                jsonschema.Draft202012Validator.check_schema(s)
                self.assertEqual(s["properties"]["tool"], {"const": t})

    def test_real_reports_validate(self):
        for t in TOOLS:
            with self.subTest(tool=t):
                self.assertEqual(errors(self.schemas, t, self.reports[t]), [])
        self.assertEqual(errors(self.schemas, "texture-refine", self.over_budget), [])
        self.assertEqual([r["measured"] for r in self.over_budget["ranks"]], [False])
        # lodbake's stages are the tools' own reports.
        for stage in self.reports["lodbake"]["stages"]:
            self.assertEqual(errors(self.schemas, stage["tool"], stage), [])

    def test_broken_reports_are_rejected(self):
        def broken(t, change):
            rep = copy.deepcopy(self.reports[t])
            change(rep)
            return errors(self.schemas, t, rep)
        self.assertTrue(broken("simplify", lambda r: r["levels"][0].pop("maxDeviation")))
        self.assertTrue(broken("parameterize", lambda r: r["total"].update(charts="2")))
        self.assertTrue(broken("texture-refine", lambda r: r["ranks"][0]["refined"].pop("E")))
        self.assertTrue(broken("texture-refine", lambda r: r["ranks"][0].pop("T0")))
        self.assertTrue(broken("texture-refine", lambda r: r["textures"][0].pop("E")))
        self.assertTrue(broken("pack", lambda r: r["levels"][1]["deviation"].update(hausdorff=-1)))
        self.assertTrue(broken("agsphere-build", lambda r: r.pop("sphere")))
        self.assertTrue(broken("compare", lambda r: r.update(pass_="x", **{"pass": "yes"})))
        self.assertTrue(broken("lodbake", lambda r: r["stages"][1]["levels"][0].pop("flips")))
        self.assertTrue(broken("lodbake", lambda r: r["stages"].reverse()))
        # The chain's LOD0 is the original (--lod0 original): several draw calls, said in lod0.
        pack = self.reports["lodbake"]["stages"][-1]
        self.assertEqual(pack["lod0"]["mode"], "original")
        self.assertEqual(pack["levels"][0]["drawCalls"], pack["lod0"]["drawCalls"])
        self.assertTrue(broken("pack", lambda r: r["lod0"].update(mode="hero")))
        self.assertTrue(broken("pack", lambda r: r["levels"][0].pop("materials")))


if __name__ == "__main__":
    unittest.main()
