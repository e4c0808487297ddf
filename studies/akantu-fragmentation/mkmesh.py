import sys
def write_msh(fname, L, n):
    with open(fname, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
        f.write("$PhysicalNames\n3\n0 1 \"left\"\n0 2 \"right\"\n1 3 \"bar\"\n$EndPhysicalNames\n")
        f.write("$Nodes\n%d\n" % (n + 1))
        for i in range(n + 1):
            f.write("%d %.17g 0 0\n" % (i + 1, L * i / n))
        f.write("$EndNodes\n$Elements\n%d\n" % (n + 2))
        f.write("1 15 2 1 1 1\n")
        f.write("2 15 2 2 2 %d\n" % (n + 1))
        for e in range(n):
            f.write("%d 1 2 3 1 %d %d\n" % (e + 3, e + 1, e + 2))
        f.write("$EndElements\n")
