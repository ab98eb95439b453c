/* The sweep's Pareto front (tools/pareto.h) on points whose front is known
 * by hand, and its SVG on the degenerate inputs. */
#include <stdio.h>
#include <unistd.h>

#include "harness.h"
#include "pareto.h"

int main(void)
{
    /* Front by hand: (1, 9), (2, 5), (4, 2), (8, 1); (3, 6) and (5, 2) are
     * dominated; the duplicate of (2, 5) is on the front too (neither
     * beats the other); NaN and negative times never are. */
    pareto_point p[] = {
        {1, 9, "a", false},  {2, 5, "b", false}, {3, 6, "c", false},
        {4, 2, "d", false},  {5, 2, "e", false}, {8, 1, "f", false},
        {2, 5, "b2", false}, {NAN, 0.1, "nan", false}, {-1, 0.1, "neg", false},
    };
    const bool want[] = {true, true, false, true, false, true, true, false, false};
    size_t n = sizeof(p) / sizeof(p[0]);
    pareto_mark(p, n);
    for (size_t i = 0; i < n; i++)
        CHECK(p[i].front == want[i], "point %s: front %d, want %d", p[i].label, p[i].front,
              want[i]);
    char path[256];
    const char *dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    snprintf(path, sizeof(path), "%s/pareto-test-%d.svg", dir, (int)getpid());
    CHECK(pareto_write_svg(path, "test <&>", p, n) == 0, "write %s", path);
    CHECK(pareto_write_svg(path, NULL, NULL, 0) == 0, "an empty plot");
    CHECK(pareto_write_svg("/nonexistent/dir/x.svg", "t", p, n) == -1, "an unwritable path");
    remove(path);
    return test_finish();
}
