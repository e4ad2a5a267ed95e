#!/usr/bin/python3
"""Writes the adversarial input files of tools/probe/probe.sh.

    gen_inputs.py IN REPO BIN

IN: the folder to write into (created; s/ scenes, p/ particles CSVs, sw/ sweep files);
REPO: the repository root (the valid inputs are edited from examples/quick and
examples/lattice); BIN: the cdpowder binary under test (its first 64 KiB are the binary inputs).
Standard library only.
"""
import os
import sys

if len(sys.argv) != 4:
    sys.exit("usage: gen_inputs.py IN REPO BIN")
IN, REPO, BIN = sys.argv[1:4]
Q = os.path.join(REPO, "examples/quick/scene.toml")
LP = os.path.join(REPO, "examples/lattice/particles.csv")
LS = os.path.join(REPO, "examples/lattice/scene.toml")


def slurp(path, binary=False):
    """The whole file (text as UTF-8), or its first 64 KiB when binary."""
    if binary:
        with open(path, "rb") as f:
            return f.read(65536)
    with open(path, encoding="utf-8") as f:
        return f.read()


q = slurp(Q)
lp = slurp(LP)
lp_lines = lp.splitlines()
hdr_i = next(i for i, l in enumerate(lp_lines) if l.startswith("x,"))
rows = lp_lines[hdr_i + 1:]


def w(rel, data, mode="w"):
    path = os.path.join(IN, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if isinstance(data, str):
        data = data.encode("utf-8")
    with open(path, "wb") as f:
        f.write(data)


def qrep(old, new, count=1):
    assert old in q, old
    return q.replace(old, new, count)


# ---------------------------------------------------------------- scenes
w("s/bom.toml", b"\xef\xbb\xbf" + q.encode())
w("s/empty.toml", b"")
w("s/comments_only.toml", "\n\n   \n# only a comment\n")
w("s/nul_value.toml", qrep("lx = 15.0", "lx = 15.0\0"))
w("s/nul_comment.toml", q + "# comment \0 with a NUL\n")
w("s/nul_only.toml", b"\0" * 1000)
w("s/elf.toml", slurp(BIN, binary=True))
w("s/longval.toml", qrep("mu = 0.3", 'mu = 0.3\ncohesion_rule = "' + "a" * 20_000_000 + '"'))
w("s/longcomment.toml", "#" + "c" * 20_000_000 + "\n" + q)
w("s/longkey.toml", qrep("[contact]", "[contact]\n" + "k" * 2_000_000 + " = 1"))
w("s/longnum.toml", qrep("lx = 15.0", "lx = 15." + "0" * 20_000_000))
w("s/unterminated_string.toml", qrep("seed = 1", 'seed = 1\ncapture_rule = "centre_distance'))
w("s/missing_value.toml", qrep("lx = 15.0", "lx = "))
w("s/dup_key.toml", qrep("lx = 15.0", "lx = 15.0\nlx = 16.0"))
w("s/dup_table.toml", q + "\n[system]\nlx = 20.0\n")
w("s/garbage_line.toml", qrep("[contact]", "this is not toml\n[contact]"))
w("s/unterminated_header.toml", qrep("[contact]", "[contact"))
w("s/unterminated_array.toml", qrep("ly = 15.0", "ly = 15.0\ngravity = [0, 0,"))
w("s/bad_escape.toml", qrep("seed = 1", 'seed = 1\ncapture_rule = "centre\\q"'))
w("s/deep_array.toml", qrep("ly = 15.0", "ly = 15.0\ngravity = " + "[" * 100000 + "]" * 100000))
w("s/deep_table.toml", qrep("ly = 15.0", "ly = 15.0\nx = " + "{a = " * 100000 + "1" + "}" * 100000))
w("s/int_overflow.toml", qrep("spheres = 100", "spheres = 99999999999999999999999"))
w("s/float_overflow.toml", qrep("lx = 15.0", "lx = 1e400"))
w("s/spheres_string.toml", qrep("spheres = 100", 'spheres = "100"'))
w("s/spheres_bool.toml", qrep("spheres = 100", "spheres = true"))
w("s/lx_date.toml", qrep("lx = 15.0", "lx = 1979-05-27"))
w("s/lx_inf.toml", qrep("lx = 15.0", "lx = inf"))
w("s/typo_section.toml", qrep("[system]", "[sytem]"))
w("s/key_wrong_section.toml", qrep("ly = 15.0", "ly = 15.0\nmu = 0.3"))
w("s/section_as_value.toml", "system = 5\n" + q.replace("[system]\nlx = 15.0\nly = 15.0\n", ""))
w("s/array_of_tables.toml", qrep("[system]", "[[system]]"))
w("s/crlf.toml", q.replace("\n", "\r\n"))
w("s/latin1.toml", q.encode() + b"# caf\xe9 \xff\n")
w("s/utf16.toml", q.encode("utf-16"))
w("s/hex_int.toml", qrep("spheres = 100", "spheres = 0x64"))
w("s/both_dep_particles.toml", q + '\n[particles]\nfile = "%s"\n' % LP)
w("s/particles_missing.toml", q.replace("[deposition]\nspheres = 100\nradius = 1.0\ncapture_radius = 3.0\nseed = 1\n",
                                         '[particles]\nfile = "nope.csv"\n'))
w("s/particles_dir.toml", q.replace("[deposition]\nspheres = 100\nradius = 1.0\ncapture_radius = 3.0\nseed = 1\n",
                                     '[particles]\nfile = "/tmp"\n'))
w("s/no_spheres.toml", q.replace("[deposition]\nspheres = 100\nradius = 1.0\ncapture_radius = 3.0\nseed = 1\n", ""))
w("s/many_errors.toml", q.replace("mu = 0.3", "mu = -0.3\nmu_rol = 1\ncohesion_rule = 5", 1).replace("lx = 15.0", "lx = -1.0", 1))
w("s/force_huge.toml", qrep("pressure = 0.0025", "force = 1e300"))
w("s/unicode_key.toml", qrep("mu = 0.3", "mu = 0.3\n\"µ\" = 0.3"))

# ---------------------------------------------------------------- particles CSV
good_hdr = "x,y,z,r"
w("p/empty.csv", "")
w("p/header_only.csv", good_hdr + "\n")
w("p/no_r.csv", "x,y,z\n" + "\n".join(",".join(r.split(",")[:3]) for r in rows) + "\n")
w("p/abc.csv", good_hdr + "\n" + rows[0] + "\n" + "1.0,2.0,abc,1\n" + "\n".join(rows[2:]) + "\n")
w("p/nan.csv", good_hdr + "\n" + rows[0] + "\n" + "nan,2.0,3.0,1\n" + "\n".join(rows[2:]) + "\n")
w("p/inf_r.csv", good_hdr + "\n" + "1.0,2.0,3.0,inf\n" + "\n".join(rows[1:]) + "\n")
w("p/neg_r.csv", good_hdr + "\n" + "1.0,2.0,3.0,-1\n" + "\n".join(rows[1:]) + "\n")
w("p/zero_r.csv", good_hdr + "\n" + "1.0,2.0,3.0,0\n" + "\n".join(rows[1:]) + "\n")
w("p/same_centre.csv", good_hdr + "\n" + rows[0] + "\n" + rows[0] + "\n" + "\n".join(rows[1:]) + "\n")
w("p/overlap.csv", good_hdr + "\n" + rows[0] + "\n" +
  ",".join([str(float(rows[0].split(",")[0]) + 0.5)] + rows[0].split(",")[1:]) + "\n" + "\n".join(rows[1:]) + "\n")
w("p/bom.csv", b"\xef\xbb\xbf" + (good_hdr + "\n" + "\n".join(rows) + "\n").encode())
w("p/crlf.csv", (good_hdr + "\n" + "\n".join(rows) + "\n").replace("\n", "\r\n"))
w("p/huge_line.csv", good_hdr + "\n" + rows[0] + "," + "9" * 20_000_000 + "\n" + "\n".join(rows[1:]) + "\n")
w("p/huge_number.csv", good_hdr + "\n" + "1." + "0" * 20_000_000 + ",2.0,3.0,1\n" + "\n".join(rows[1:]) + "\n")
w("p/unknown_col.csv", "x,y,z,r,colour\n" + "\n".join(r + ",red" for r in rows) + "\n")
w("p/dup_col.csv", "x,y,z,r,x\n" + "\n".join(r + ",5.0" for r in rows) + "\n")
w("p/short_row.csv", good_hdr + "\n" + rows[0] + "\n1.0,2.0,3.0\n" + "\n".join(rows[2:]) + "\n")
w("p/long_row.csv", good_hdr + "\n" + rows[0] + "\n1.0,2.0,3.0,1,7\n" + "\n".join(rows[2:]) + "\n")
w("p/fixed_maybe.csv", "x,y,z,r,fixed\n" + "\n".join(r + ",maybe" for r in rows) + "\n")
w("p/outside_cell.csv", good_hdr + "\n" + "1000.5,-777.25,5.0,1\n" + "\n".join(rows[1:]) + "\n")
w("p/below_wall.csv", good_hdr + "\n" + "7.0,7.0,-3.0,1\n" + "\n".join(rows[1:]) + "\n")
w("p/big_r.csv", good_hdr + "\n" + "7.0,7.0,50.0,40\n" + "\n".join(rows[1:]) + "\n")
w("p/nul.csv", (good_hdr + "\n" + rows[0] + "\n" + "1.0,2.0,\0" + "3.0,1\n" + "\n".join(rows[2:]) + "\n").encode())
w("p/semicolon.csv", "x;y;z;r\n" + "\n".join(r.replace(",", ";") for r in rows) + "\n")
w("p/e400.csv", good_hdr + "\n" + "1.0,2.0,1e400,1\n" + "\n".join(rows[1:]) + "\n")
w("p/binary.csv", slurp(BIN, binary=True))
w("p/trailing_comma.csv", good_hdr + ",\n" + "\n".join(r + "," for r in rows) + "\n")
w("p/quoted.csv", '"x","y","z","r"\n' + "\n".join(",".join('"%s"' % v for v in r.split(",")) for r in rows) + "\n")
w("p/huge_velocity.csv", "x,y,z,r,vx\n" + "\n".join(r + ",1e300" for r in rows) + "\n")
w("p/all_fixed.csv", "x,y,z,r,fixed\n" + "\n".join(r + ",1" for r in rows) + "\n")
w("p/scene_rel/scene.toml", slurp(LS).replace(
    'file = "particles.csv"', 'file = "missing_relative.csv"'))

# ---------------------------------------------------------------- sweep files
HEAD = 'scene = "%s"\n' % Q


def sw(name, body):
    w("sw/" + name, body)


sw("set_malformed.toml", HEAD + 'seeds = 1\nset = ["contact.mu"]\n')
sw("set_unknown.toml", HEAD + 'seeds = 1\nset = ["contact.muu=1"]\n')
sw("set_not_array.toml", HEAD + 'seeds = 1\nset = "contact.mu=1"\n')
sw("set_bad_value.toml", HEAD + 'seeds = 1\nset = ["contact.mu=-5"]\n')
sw("grid_out_of_range.toml", HEAD + "seeds = 1\n[grid.contact]\nmu_roll = [-1.0]\n")
sw("grid_empty.toml", HEAD + "seeds = 1\n[grid.contact]\nmu_roll = []\n")
sw("grid_repeat.toml", HEAD + "seeds = 1\n[grid.contact]\nmu_roll = [1.0, 1.0]\n")
sw("grid_mixed.toml", HEAD + 'seeds = 1\n[grid.contact]\nmu_roll = [1.0, "a"]\n')
sw("grid_unknown_key.toml", HEAD + "seeds = 1\n[grid.contact]\nmu_rol = [1.0]\n")
sw("grid_nested.toml", HEAD + "seeds = 1\n[grid.contact]\nmu_roll = [[1.0]]\n")
sw("grid_scalar.toml", HEAD + "seeds = 1\n[grid.contact]\nmu_roll = 1.0\n")
sw("grid_seed_key.toml", HEAD + "seeds = 1\n[grid.deposition]\nseed = [1, 2]\n")
sw("unknown_top.toml", HEAD + "seedz = 2\n")
sw("seeds_zero.toml", HEAD + "seeds = 0\n")
sw("seeds_dup.toml", HEAD + "seeds = [1, 1]\n")
sw("seeds_negative.toml", HEAD + "seeds = -1\n")
sw("seeds_too_many.toml", HEAD + "seeds = 100001\n")
sw("seeds_empty_list.toml", HEAD + "seeds = []\n")
sw("seeds_float.toml", HEAD + "seeds = 1.5\n")
sw("seeds_neg_in_list.toml", HEAD + "seeds = [1, -3]\n")
sw("scene_missing.toml", 'scene = "nope_scene.toml"\nseeds = 1\n')
sw("no_scene.toml", "seeds = 1\n")
sw("scene_dir.toml", 'scene = "/tmp"\nseeds = 1\n')
sw("scene_not_string.toml", "scene = 5\nseeds = 1\n")
sw("points_dup.toml", HEAD + "seeds = 1\n[[points]]\ncontact = { mu_roll = 1 }\n[[points]]\ncontact = { mu_roll = 1.0 }\n")
sw("points_unknown.toml", HEAD + "seeds = 1\n[[points]]\ncontact = { mu_rol = 1 }\n")
sw("seed_keys_unknown.toml", HEAD + 'seeds = 1\nseed_keys = ["foo.bar"]\n')
sw("empty.toml", "")
sw("bad_scene_content.toml", 'scene = "%s"\nseeds = 1\n' % os.path.join(IN, "s/typo_section.toml"))
sw("malformed.toml", HEAD + "seeds = [1, 2\n")
sw("valid1.toml", HEAD + "seeds = 1\n[grid.contact]\nmu_roll = [1.0]\n")
sw("self_scene.toml", 'scene = "self_scene.toml"\nseeds = 1\n')
