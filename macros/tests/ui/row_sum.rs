use tessgen_macros::scheme;

fn main() {
    let _ = scheme! {
        scheme row_sum {
            facet quad;
            vertex {
                f[j] = (4 * p + 2 * p[2 * j]) / 9;
                e[j] = (f[j - 1] + f[j]) / 2;
                v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
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
