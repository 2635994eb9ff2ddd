#include "falling_ball.h"

int main(void)
{
    return falling_ball_checks_out();
}
