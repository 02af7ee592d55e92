// include/hyst.h from C++: the header compiles as C++11 (its functions inside extern "C") and
// links against the same library. Runs the operator pair once and checks the round trip.

#include <cmath>
#include <cstdio>
#include <cstring>

#include "hyst.h"

int main()
{
    hyst_operator h, inverse;
    std::memset(&h, 0, sizeof h);
    std::memset(&inverse, 0, sizeof inverse);
    if (hyst_operator_init_direct(&h, 0.2, 8.0) != HYST_OK ||
        hyst_operator_init_inverse(&inverse, 0.2, 8.0) != HYST_OK) {
        std::fprintf(stderr, "header_cpp: init failed\n");
        return 1;
    }
    double worst = 0.0;
    for (int k = 0; k < 500; ++k) {
        const double x = std::sin(0.03 * k);
        double y = 0.0, back = 0.0;
        if (hyst_operator_step(&h, x, &y) != HYST_OK ||
            hyst_operator_step(&inverse, y, &back) != HYST_OK) {
            std::fprintf(stderr, "header_cpp: step failed\n");
            return 1;
        }
        worst = std::fmax(worst, std::fabs(back - x));
    }
    hyst_memory_f32 memory32 = hyst_memory_f32();
    hyst_operator_f32 zeroed = hyst_operator_f32();
    const int32_t status = hyst_operator_get_memory_f32(&zeroed, &memory32);
    if (worst > 1e-12 || status != HYST_ERR_NOT_INITIALISED) {
        std::fprintf(stderr, "header_cpp: round trip %g, status %d (%s)\n", worst,
                     static_cast<int>(status), hyst_status_message(status));
        return 1;
    }
    std::printf("header_cpp: ok (C++ %ld, round trip within %g)\n", static_cast<long>(__cplusplus),
                worst);
    return 0;
}
