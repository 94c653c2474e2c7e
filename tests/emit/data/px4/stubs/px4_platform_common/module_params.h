// Test stub: ModuleParams and DEFINE_PARAMETERS as PX4 spells them.
// The test writes px4_params_generated.h (enum class px4::params) from module.yaml.
#pragma once

#include "px4_params_generated.h"

class ModuleParams
{
public:
	virtual ~ModuleParams() = default;
};

template<px4::params P> struct ParamFloat { float get() const { return 0.f; } };
template<px4::params P> struct ParamInt { int get() const { return 0; } };
template<px4::params P> struct ParamBool { bool get() const { return false; } };

// DEFINE_PARAMETERS((ParamFloat<px4::params::A>) _param_a, ...): each "(Type) name" becomes "Type name;".
#define _PX4_STRIP(...) __VA_ARGS__
#define _PX4_DECL(x) _PX4_STRIP x;
#define _PX4_N(_1, _2, _3, _4, _5, _6, _7, _8, _9, _10, _11, _12, _13, _14, _15, _16, N, ...) N
#define _PX4_E1(a) _PX4_DECL(a)
#define _PX4_E2(a, ...) _PX4_DECL(a) _PX4_E1(__VA_ARGS__)
#define _PX4_E3(a, ...) _PX4_DECL(a) _PX4_E2(__VA_ARGS__)
#define _PX4_E4(a, ...) _PX4_DECL(a) _PX4_E3(__VA_ARGS__)
#define _PX4_E5(a, ...) _PX4_DECL(a) _PX4_E4(__VA_ARGS__)
#define _PX4_E6(a, ...) _PX4_DECL(a) _PX4_E5(__VA_ARGS__)
#define _PX4_E7(a, ...) _PX4_DECL(a) _PX4_E6(__VA_ARGS__)
#define _PX4_E8(a, ...) _PX4_DECL(a) _PX4_E7(__VA_ARGS__)
#define _PX4_E9(a, ...) _PX4_DECL(a) _PX4_E8(__VA_ARGS__)
#define _PX4_E10(a, ...) _PX4_DECL(a) _PX4_E9(__VA_ARGS__)
#define _PX4_E11(a, ...) _PX4_DECL(a) _PX4_E10(__VA_ARGS__)
#define _PX4_E12(a, ...) _PX4_DECL(a) _PX4_E11(__VA_ARGS__)
#define _PX4_E13(a, ...) _PX4_DECL(a) _PX4_E12(__VA_ARGS__)
#define _PX4_E14(a, ...) _PX4_DECL(a) _PX4_E13(__VA_ARGS__)
#define _PX4_E15(a, ...) _PX4_DECL(a) _PX4_E14(__VA_ARGS__)
#define _PX4_E16(a, ...) _PX4_DECL(a) _PX4_E15(__VA_ARGS__)
#define _PX4_EACH(...) _PX4_N(__VA_ARGS__, _PX4_E16, _PX4_E15, _PX4_E14, _PX4_E13, _PX4_E12, _PX4_E11, _PX4_E10, \
	_PX4_E9, _PX4_E8, _PX4_E7, _PX4_E6, _PX4_E5, _PX4_E4, _PX4_E3, _PX4_E2, _PX4_E1, _)(__VA_ARGS__)
#define DEFINE_PARAMETERS(...) _PX4_EACH(__VA_ARGS__)
