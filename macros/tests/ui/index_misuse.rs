use tessgen_macros::scheme;

fn main() {
    let _ = scheme! {
        scheme index_misuse {
            facet quad;
            vertex {
                f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
                e[j] = (f[j - 1] + f[j]) / 2;
                v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
                t[j] = (v + e) / 2;
            }
            patch ordinary: bicubic {
                out b00[i] = v(i);
                out b10[i] = e(i, 0);
                out b01[i] = e(i, 1);
                out b11[i] = f(i, 0);
            }
        }
    };
}
