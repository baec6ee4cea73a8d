"""Ground truth for the f64 reference formulas, from the closed forms evaluated in mpmath at
100 significant digits (and checked against 150 digits and, for small N, against the direct
double sums). Writes host-tests/data/reference_truth.csv; host-tests/tests/reference.rs
reads it. CI re-runs this script and checks that the committed file is what it writes.

Columns: alpha, n, b (REFERENCE (a) eq 32's B(alpha, N)), v (REFERENCE (c)(iii)'s
V(N, alpha) = sum_{i,j=1..N} i j q^|i-j|), each to 25 significant digits.
Run: python3 reference_truth.py > ../data/reference_truth.csv
"""
import mpmath as mp

ALPHAS = ["1e-9", "1e-7", "1e-6", "1e-4", "1e-3", "0.01", "0.1", "0.5", "1", "2", "3.14159"]
NS = [1, 2, 3, 5, 10, 100, 1000, 10**4, 10**6, 10**7, 10**9]


def b_closed(alpha, n):
    q = mp.exp(-alpha)
    return ((mp.mpf(n) / 2) * (1 - mp.exp(-2 * alpha)) - q + mp.exp(-(n + 1) * alpha)) / (1 - q) ** 2


def v_closed(alpha, n):
    q = mp.exp(-alpha)
    u = 1 - q
    n = mp.mpf(n)
    num = (2 * n**3 * u**3 * (1 + q) + 3 * n**2 * u**2 * (1 - 2 * q - q**2)
           + n * u**2 * (1 - 6 * q - q**2) + 12 * q**2 * (1 - q**n * (1 + n * u)))
    return num / (6 * u**4)


def b_direct(alpha, n):
    q = mp.exp(-alpha)
    return sum(q ** abs(i - k) for i in range(1, n + 1) for k in range(1, n + 1)) / 2


def v_direct(alpha, n):
    q = mp.exp(-alpha)
    return sum(i * k * q ** abs(i - k) for i in range(1, n + 1) for k in range(1, n + 1))


def main():
    print("alpha,n,b,v")
    for a_text in ALPHAS:
        for n in NS:
            with mp.workdps(100):
                a = mp.mpf(a_text)
                b, v = b_closed(a, n), v_closed(a, n)
                if n <= 10:
                    for got, want in ((b, b_direct(a, n)), (v, v_direct(a, n))):
                        assert abs(got / want - 1) < mp.mpf("1e-40"), (a_text, n)
            with mp.workdps(150):
                a = mp.mpf(a_text)
                b2, v2 = b_closed(a, n), v_closed(a, n)
            assert abs(b / b2 - 1) < mp.mpf("1e-40") and abs(v / v2 - 1) < mp.mpf("1e-40")
            print(f"{a_text},{n},{mp.nstr(b, 25)},{mp.nstr(v, 25)}")


if __name__ == "__main__":
    main()
