"""The command line every house check shares: ROOT to check a tree, --self-test to prove the
check catches what it looks for. Exits with the check's status (0: the tree keeps the rule)."""
import sys


def run(check, self_test, usage):
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        sys.exit(self_test())
    if len(sys.argv) != 2:
        print(usage)
        sys.exit(2)
    sys.exit(check(sys.argv[1]))
